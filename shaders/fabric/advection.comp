#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The advection of fabric/advection.frag as a compute shader (the same common/advection_step.glsl and
// common/advection_restart.glsl), for GPUs whose fragment pipeline is the narrow part of the chip
// (AdvectionPass::setCompute): the Eq. 12 iteration, or with RESET the restart from beta into both
// ping-pong textures (RESET SILHOUETTES: finding and writing the silhouettes too).
// An iteration does not write blocked pixels: the restart gave them the blocked state in both ping-pong
// textures, as the fragment pass's early depth test leaves the background.
layout(local_size_x = 8, local_size_y = 8) in;
#define COMPUTE
#include "common/advection_step.glsl"
#include "common/advection_restart.glsl"
layout(binding = IMAGE_NEXT1, r32f) uniform writeonly image2D o_p1; // RESET: the first ping-pong texture
layout(binding = IMAGE_NEXT2, r32f) uniform writeonly image2D o_p2;
#ifdef THIRD
layout(binding = IMAGE_NEXT3, r32f) uniform writeonly image2D o_p3;
#endif
#ifdef RESET
layout(binding = IMAGE_OTHER1, r32f) uniform writeonly image2D o_p1b; // the second ping-pong texture
layout(binding = IMAGE_OTHER2, r32f) uniform writeonly image2D o_p2b;
#ifdef THIRD
layout(binding = IMAGE_OTHER3, r32f) uniform writeonly image2D o_p3b;
#endif
#ifdef SILHOUETTES
layout(binding = IMAGE_EDGE, r8) uniform writeonly image2D o_edge;
#endif

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, textureSize(u_surface, 0)))) return;
  vec3 state;
  float edge;
  restartPixel(p, state, edge);
  imageStore(o_p1, p, vec4(state.x));
  imageStore(o_p2, p, vec4(state.y));
  imageStore(o_p1b, p, vec4(state.x));
  imageStore(o_p2b, p, vec4(state.y));
#ifdef THIRD
  imageStore(o_p3, p, vec4(state.z));
  imageStore(o_p3b, p, vec4(state.z));
#endif
#ifdef SILHOUETTES
  imageStore(o_edge, p, vec4(edge));
#endif
}
#else
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, textureSize(u_prev1, 0)))) return;
  vec3 next, here;
  float beta;
  if (!advectionStep(p, next, here, beta)) return;
  imageStore(o_p1, p, vec4(next.x));
  imageStore(o_p2, p, vec4(next.y));
#ifdef THIRD
  imageStore(o_p3, p, vec4(next.z));
#endif
}
#endif
