#version 450 core
// Advection pass (paper §2.5, Eq. 12), both eigenvector fields at once:
//   p_{i+1} = k beta + (1 - k) (p_i(x + v) + p_i(x - v)) / 2.
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
layout(binding = UNIT_PREV1) uniform sampler2D u_prev1;          // p1, bilinear, clamp to edge
layout(binding = UNIT_PREV2) uniform sampler2D u_prev2;          // p2
layout(binding = UNIT_VECTORS) uniform usampler2D u_vectors;     // snorm16 v1.xy, snorm16 v2.xy (max-norm 1), beta bits
layout(binding = UNIT_SURFACE) uniform sampler2D u_surface;      // RESET: .r beta, .a coverage
layout(binding = UNIT_SILHOUETTE) uniform sampler2D u_silhouette; // RESET: .r 1 on silhouettes and off the surface
#ifdef THIRD
layout(binding = UNIT_PREV3) uniform sampler2D u_prev3;          // p3
#endif
#ifdef REPROJECT
layout(binding = UNIT_HISTORY_SURFACE) uniform sampler2D u_histSurface; // previous frame's surface (.b depth)
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth;                // this frame's window depth
uniform mat4 u_windowToWorld;     // (pixel x, y, window depth, 1) of this frame -> world
uniform mat4 u_worldToPrevWindow; // world -> previous frame's (pixel x, y)
uniform mat4 u_worldToPrevEye;    // world -> previous frame's eye space
uniform float u_depthTol;         // mm
#endif

const float BLOCKED = -1e20;
// Fibre sets: the second field advects the complementary noise 1 - beta, so the threads of two crossing
// populations interleave instead of brightening the same noise spots into crosses.
uniform bool u_complementSecond = false;

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
#ifdef COUNT
layout(binding = COUNTER_CHANGED, offset = 0) uniform atomic_uint u_changed;
uniform float u_epsilon;
#endif
uniform float u_k;
uniform float u_step; // pixels per unit of the max-norm scaled vectors

layout(location = 0) out float o_p1;
layout(location = 1) out float o_p2;
#ifdef THIRD
layout(location = 2) out float o_p3;
#endif

// The mean of p at x + d and x - d, with p_i(x) standing in for a blocked sample.
float advect(sampler2D prev, vec2 x, vec2 d, vec2 inv, float here) {
  float a = texture(prev, (x + d) * inv).r, b = texture(prev, (x - d) * inv).r;
  return 0.5 * ((a < 0.0 ? here : a) + (b < 0.0 ? here : b));
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec2 s = vec2(texelFetch(u_prev1, p, 0).r, texelFetch(u_prev2, p, 0).r);
  vec2 inv = 1.0 / vec2(textureSize(u_prev1, 0));
  vec2 x = gl_FragCoord.xy;
  uvec4 q = texelFetch(u_vectors, p, 0);
  vec4 v = vec4(unpackSnorm2x16(q.x), unpackSnorm2x16(q.y)) * u_step;
  float beta = uintBitsToFloat(q.z);
  // A zero vector (no direction) averages p_i(x) with itself.
  vec2 avg = vec2(advect(u_prev1, x, v.xy, inv, s.r), advect(u_prev2, x, v.zw, inv, s.g));
  vec2 next = u_k * vec2(beta, u_complementSecond ? 1.0 - beta : beta) + (1.0 - u_k) * avg;
  bool blocked = s.r < 0.0;
#ifdef THIRD
  float s3 = texelFetch(u_prev3, p, 0).r;
  float next3 = u_k * beta + (1.0 - u_k) * advect(u_prev3, x, unpackSnorm2x16(q.w) * u_step, inv, s3);
  o_p3 = blocked ? s3 : next3;
#endif
#ifdef COUNT
#ifdef THIRD
  bool changed3 = abs(next3 - s3) > u_epsilon;
#else
  bool changed3 = false;
#endif
  if (!blocked && (changed3 || any(greaterThan(abs(next - s), vec2(u_epsilon))))) atomicCounterIncrement(u_changed);
#endif
  vec2 out2 = blocked ? s : next;
  o_p1 = out2.x;
  o_p2 = out2.y;
}
#endif
