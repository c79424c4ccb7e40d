#version 450 core
// Advection pass (paper §2.5, Eq. 12), both eigenvector fields at once (red: v1, green: v2):
//   p_{i+1} = k beta + (1 - k) (p_i(x + v) + p_i(x - v)) / 2.
// Samples are bilinear in pixel units. A sample that falls on a silhouette or off the surface is replaced
// by p_i(x), so nothing is carried across edges. Pixels whose value changed by more than u_epsilon in
// either field are counted in an atomic counter (the stopping criterion of §2.5).
layout(binding = 0) uniform sampler2D u_prev;       // p_i (rg)
layout(binding = 1) uniform sampler2D u_vectors;    // v1.xy, v2.xy
layout(binding = 2) uniform sampler2D u_surface;    // .r beta, .a coverage
layout(binding = 3) uniform sampler2D u_silhouette; // .r e
layout(binding = 0, offset = 0) uniform atomic_uint u_changed;

uniform float u_k;
uniform float u_step;     // pixels per unit of the max-norm scaled vectors
uniform float u_epsilon;
uniform bool u_count;

out vec2 o_p;

bool blocked(vec2 pos) {
  ivec2 q = ivec2(floor(pos));
  ivec2 size = textureSize(u_surface, 0);
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return true;
  return texelFetch(u_surface, q, 0).a < 0.5 || texelFetch(u_silhouette, q, 0).r > 0.5;
}

float along(vec2 x, vec2 v, int channel, float here) {
  if (v == vec2(0.0)) return here;
  vec2 inv = 1.0 / vec2(textureSize(u_prev, 0));
  vec2 a = x + v, b = x - v;
  float pa = blocked(a) ? here : texture(u_prev, a * inv)[channel];
  float pb = blocked(b) ? here : texture(u_prev, b * inv)[channel];
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
  vec2 next;
  next.r = u_k * beta + (1.0 - u_k) * along(x, v.xy, 0, prev.r);
  next.g = u_k * beta + (1.0 - u_k) * along(x, v.zw, 1, prev.g);
  if (u_count && any(greaterThan(abs(next - prev), vec2(u_epsilon)))) atomicCounterIncrement(u_changed);
  o_p = next;
}
