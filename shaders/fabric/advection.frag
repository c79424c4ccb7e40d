#version 450 core
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
// a third field p3 (fibre sets' third population) advects along the vectors' .w direction; RESET THIRD also
// writes p3.
// RESET REPROJECT (movies, two fields) starts from the previous frame's state instead of beta where the same
// surface point was visible there: the pixel's world position (from the window depth) is projected into the
// previous frame, whose kept state is sampled bilinearly when its linear depth there agrees within
// u_depthTol mm and no blocked texel touches the sample; elsewhere (newly visible surface) p_0 = beta.
#include "common/advection_step.glsl"
layout(binding = UNIT_SURFACE) uniform sampler2D u_surface;      // RESET: .r beta, .a coverage
layout(binding = UNIT_SILHOUETTE) uniform sampler2D u_silhouette; // RESET: .r 1 on silhouettes and off the surface
#ifdef REPROJECT
layout(binding = UNIT_HISTORY_SURFACE) uniform sampler2D u_histSurface; // previous frame's surface (.b depth)
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth;                // this frame's window depth
uniform mat4 u_windowToWorld;     // (pixel x, y, window depth, 1) of this frame -> world
uniform mat4 u_worldToPrevWindow; // world -> previous frame's (pixel x, y)
uniform mat4 u_worldToPrevEye;    // world -> previous frame's eye space
uniform float u_depthTol;         // mm
#endif

#ifdef FAR_PLANE
layout(early_fragment_tests) in;
#endif

#ifdef RESET
#ifdef SILHOUETTES
// The restart of a frame whose projection changed finds the silhouettes itself (the silhouette pass's test,
// common/silhouette.glsl) and writes them for the composite and later frames: one fullscreen pass fewer.
#include "common/silhouette.glsl"
uniform float u_threshold;  // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background; // linear depth assigned to empty pixels
#endif
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
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(u_surface, p, 0);
  ivec2 size = textureSize(u_surface, 0);
  bool ring = p.x == 0 || p.y == 0 || p.x == size.x - 1 || p.y == size.y - 1;
#ifdef SILHOUETTES
  float e = silhouetteEdge(u_surface, floor(gl_FragCoord.xy), u_threshold, u_background);
  o_edge = e;
  bool blocked = s.a < 0.5 || ring || e > 0.5;
#else
  bool blocked = s.a < 0.5 || ring || texelFetch(u_silhouette, p, 0).r > 0.5;
#endif
  float p1 = s.r, p2 = u_complementSecond ? 1.0 - s.r : s.r;
#ifdef REPROJECT
  if (!blocked) {
    vec4 w = u_windowToWorld * vec4(gl_FragCoord.xy, texelFetch(u_depth, p, 0).r, 1.0);
    w /= w.w;
    vec4 q = u_worldToPrevWindow * w;
    vec2 x = q.xy / q.w;
    if (all(greaterThanEqual(x, vec2(1.0))) && all(lessThan(x, vec2(size - 1)))) {
      vec4 h = texelFetch(u_histSurface, ivec2(x), 0);
      if (h.a > 0.5 && abs(h.b + (u_worldToPrevEye * w).z) < u_depthTol) {
        vec2 uv = x / vec2(size);
        float a = texture(u_prev1, uv).r, b = texture(u_prev2, uv).r;
        if (a >= 0.0 && b >= 0.0) {
          p1 = a;
          p2 = b;
        }
      }
    }
  }
#endif
  o_p1 = o_p1b = blocked ? BLOCKED : p1;
  o_p2 = o_p2b = blocked ? BLOCKED : p2;
#ifdef THIRD
  o_p3 = o_p3b = blocked ? BLOCKED : s.r;
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
  bool moving = advectionStep(ivec2(gl_FragCoord.xy), next, here);
  o_p1 = moving ? next.x : here.x;
  o_p2 = moving ? next.y : here.y;
#ifdef THIRD
  o_p3 = moving ? next.z : here.z;
#endif
}
#endif
