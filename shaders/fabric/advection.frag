#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Advection pass (paper §2.5, Eq. 12), both eigenvector fields at once:
//   p_{i+1} = k beta + (1 - k) (p_i(x + v) + p_i(x - v)) / 2
// (one iteration: common/advection_step.glsl, also run as a compute shader by fabric/advection.comp).
// The state is p1 and p2 in two single-channel textures; blocked pixels (silhouettes, off the surface, and
// the outermost ring of the target, which clamp-to-edge repeats beyond the edge) hold BLOCKED (-1e20).
// A bilinear sample whose footprint gives any weight to a blocked texel is therefore negative: such a
// sample is replaced by p_i(x), so nothing is carried across silhouettes or in from the background.
// Blocked pixels keep their state. With COUNT, pixels whose value changed by more than u_epsilon are
// counted in an atomic counter (the stopping criterion of §2.5). With RESET, the pass initialises both
// ping-pong textures at once: p1 = p2 = beta, or BLOCKED; RESET SILHOUETTES also finds the silhouettes
// (instead of reading the silhouette pass's target) and writes them there. With FAR_PLANE, only covered
// pixels are shaded (early depth test against the surface's depth; see common/fullscreen.vert). With THIRD,
// a third field p3 (fibre sets' third population) advects along the fibre target's .w direction; RESET
// THIRD also writes p3.
// RESET REPROJECT (movies, two fields) starts from the previous frame's state instead of beta where the same
// surface point was visible there: the pixel's world position (from the window depth) is projected into the
// previous frame, whose kept state is sampled bilinearly when its linear depth there agrees within
// u_depthTol mm and no blocked texel touches the sample; elsewhere (newly visible surface) p_0 = beta.
#include "common/advection_step.glsl"
#include "common/advection_restart.glsl"

#ifdef FAR_PLANE
layout(early_fragment_tests) in;
#endif

#ifdef RESET
layout(location = 0) out float o_p1;  // both ping-pong textures
layout(location = 1) out float o_p2;
layout(location = 2) out float o_p1b;
layout(location = 3) out float o_p2b;
#ifdef THIRD
layout(location = 4) out float o_p3;
layout(location = 5) out float o_p3b;
#endif
#ifdef SILHOUETTES
#ifdef THIRD
layout(location = 6) out float o_edge;
#else
layout(location = 4) out float o_edge;
#endif
#endif

void main() {
  vec3 state;
  float edge;
  restartPixel(ivec2(gl_FragCoord.xy), state, edge);
  o_p1 = o_p1b = state.x;
  o_p2 = o_p2b = state.y;
#ifdef THIRD
  o_p3 = o_p3b = state.z;
#endif
#ifdef SILHOUETTES
  o_edge = edge;
#endif
}
#else
layout(location = 0) out float o_p1;
layout(location = 1) out float o_p2;
#ifdef THIRD
layout(location = 2) out float o_p3;
#endif

void main() {
  vec3 next, here;
  float beta;
  bool moving = advectionStep(ivec2(gl_FragCoord.xy), next, here, beta);
  o_p1 = moving ? next.x : here.x;
  o_p2 = moving ? next.y : here.y;
#ifdef THIRD
  o_p3 = moving ? next.z : here.z;
#endif
}
#endif
