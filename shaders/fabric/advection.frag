#version 450 core
// Advection pass (paper §2.5, Eq. 12), both eigenvector fields at once (red: v1, green: v2):
//   p_{i+1} = k beta + (1 - k) (p_i(x + v) + p_i(x - v)) / 2.
// Samples are bilinear in pixel units. A sample that falls on a silhouette or off the surface is replaced
// by p_i(x), so nothing is carried across edges. Pixels whose value changed by more than u_epsilon in
// either field are counted in an atomic counter (the stopping criterion of §2.5).
layout(binding = 0) uniform sampler2D u_prev;       // p_i (rg)
layout(binding = 1) uniform sampler2D u_vectors;    // v1.xy, v2.xy
layout(binding = 2) uniform sampler2D u_surface;    // .r beta, .a coverage
layout(binding = 3) uniform sampler2D u_silhouette; // .r e (1 also off the surface; border 1, nearest)
layout(binding = 0, offset = 0) uniform atomic_uint u_changed;

uniform float u_k;
uniform float u_step;     // pixels per unit of the max-norm scaled vectors
uniform float u_epsilon;
uniform bool u_count;

out vec2 o_p;

float along(vec2 x, vec2 v, vec2 inv, int channel, float here) {
  vec2 a = (x + v) * inv, b = (x - v) * inv;
  // Nearest fetch of the silhouette texture; its border is 1, so leaving the target also blocks.
  float pa = texture(u_silhouette, a).r > 0.5 ? here : texture(u_prev, a)[channel];
  float pb = texture(u_silhouette, b).r > 0.5 ? here : texture(u_prev, b)[channel];
  return 0.5 * (pa + pb);
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(u_surface, p, 0);
  if (s.a < 0.5) {
    o_p = vec2(0.0);
    return;
  }
  float beta = s.r;
  vec2 x = gl_FragCoord.xy;
  vec2 prev = texelFetch(u_prev, p, 0).rg;
  vec4 v = texelFetch(u_vectors, p, 0) * u_step;
  vec2 inv = 1.0 / vec2(textureSize(u_prev, 0));
  vec2 avg = prev;
  if (v.xy != vec2(0.0)) avg.r = along(x, v.xy, inv, 0, prev.r);
  if (v.zw != vec2(0.0)) avg.g = along(x, v.zw, inv, 1, prev.g);
  vec2 next = u_k * beta + (1.0 - u_k) * avg;
  if (u_count && any(greaterThan(abs(next - prev), vec2(u_epsilon)))) atomicCounterIncrement(u_changed);
  o_p = next;
}
