#version 450 core
// Advection pass (paper §2.5, Eq. 12), both eigenvector fields at once:
//   p_{i+1} = k beta + (1 - k) (p_i(x + v) + p_i(x - v)) / 2.
// The state texture holds (p1, p2, beta, blocked) per pixel; blocked = 1 on silhouettes and off the
// surface, and its border is (0, 0, 0, 1). One bilinear fetch per sample gives the advected value and,
// in .a, whether any texel of its footprint is blocked: such a sample is replaced by p_i(x), so nothing is
// carried across silhouettes or in from the background. Blocked pixels keep their state. Pixels whose
// value changed by more than u_epsilon are counted in an atomic counter (the stopping criterion of §2.5).
// With RESET defined, the pass initialises the state: p1 = p2 = beta, blocked from the silhouette pass,
// into both ping-pong textures at once. With FAR_PLANE, only covered pixels are shaded (early depth test
// against the surface's depth; see common/fullscreen.vert).
layout(binding = 0) uniform sampler2D u_prev;       // (p1, p2, beta, blocked), bilinear, border blocked
layout(binding = 1) uniform sampler2D u_vectors;    // v1.xy, v2.xy (pixels, max-norm 1)
layout(binding = 2) uniform sampler2D u_surface;    // RESET: .r beta, .a coverage
layout(binding = 3) uniform sampler2D u_silhouette; // RESET: .r 1 on silhouettes and off the surface
layout(binding = 0, offset = 0) uniform atomic_uint u_changed;

uniform float u_k;
uniform float u_step;     // pixels per unit of the max-norm scaled vectors
uniform float u_epsilon;
uniform bool u_count;

#ifdef FAR_PLANE
layout(early_fragment_tests) in;
#endif

#ifdef RESET
layout(location = 0) out vec4 o_state;
layout(location = 1) out vec4 o_state2;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(u_surface, p, 0);
  float blocked = (s.a < 0.5 || texelFetch(u_silhouette, p, 0).r > 0.5) ? 1.0 : 0.0;
  float beta = s.a < 0.5 ? 0.0 : s.r;
  o_state = vec4(beta, beta, beta, blocked);
  o_state2 = o_state;
}
#else
out vec4 o_state;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(u_prev, p, 0);
  if (s.a > 0.5) { // silhouette or background: unchanged
    o_state = s;
    return;
  }
  vec2 inv = 1.0 / vec2(textureSize(u_prev, 0));
  vec2 x = gl_FragCoord.xy;
  vec4 v = texelFetch(u_vectors, p, 0) * u_step;
  vec2 avg = s.rg;
  if (v.xy != vec2(0.0)) {
    vec4 a = texture(u_prev, (x + v.xy) * inv), b = texture(u_prev, (x - v.xy) * inv);
    avg.r = 0.5 * ((a.a > 0.0 ? s.r : a.r) + (b.a > 0.0 ? s.r : b.r));
  }
  if (v.zw != vec2(0.0)) {
    vec4 a = texture(u_prev, (x + v.zw) * inv), b = texture(u_prev, (x - v.zw) * inv);
    avg.g = 0.5 * ((a.a > 0.0 ? s.g : a.g) + (b.a > 0.0 ? s.g : b.g));
  }
  vec2 next = u_k * s.b + (1.0 - u_k) * avg;
  if (u_count && any(greaterThan(abs(next - s.rg), vec2(u_epsilon)))) atomicCounterIncrement(u_changed);
  o_state = vec4(next, s.b, 0.0);
}
#endif
