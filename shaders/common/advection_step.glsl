// SPDX-License-Identifier: GPL-3.0-or-later
// The advection state and one Eq. 12 iteration at a pixel (paper §2.5), shared by the fragment pass
// (fabric/advection.frag) and its compute twin (fabric/advection.comp), so both compute the same values.
// The iteration reads single texels as images: on llvmpipe an image load is inlined, where a texelFetch or
// a sample calls a generated function (about three times the instructions).
// INTEGER_STEP: the step is a whole number of pixels. The vectors have max-norm 1 (their larger component
// exactly +-1), so every sample p_i(x +- v) lies on a texel column (or row) and is the linear interpolation
// of the two texels of that column it falls between: two image loads, where a bilinear sample fetches four
// texels through the sampler. The same value as the bilinear sample in exact arithmetic, with weights in
// float rather than the sampler's rounding of texture coordinates: a weight the geometry makes zero is zero,
// so a blocked texel beside the footprint never blocks it. Otherwise the samples are bilinear (u_prev1..3).

layout(binding = UNIT_PREV1) uniform sampler2D u_prev1;          // p1, bilinear, clamp to edge
layout(binding = UNIT_PREV2) uniform sampler2D u_prev2;          // p2
#ifdef THIRD
layout(binding = UNIT_PREV3) uniform sampler2D u_prev3;          // p3
#endif

const float BLOCKED = -1e20;

// The iteration's parameters: k (Eq. 12), the step (pixels per unit of the max-norm scaled vectors), the
// complement flag (fibre sets: the second field advects the complementary noise 1 - beta, so the threads of
// two crossing populations interleave instead of brightening the same noise spots into crosses) and epsilon
// (COUNT). The fragment pass receives them as flat inputs from fabric/advection.vert, which reads the
// uniforms; the compute twin (COMPUTE) reads the uniforms.
#ifdef COMPUTE
uniform float u_k;
uniform float u_step;
uniform bool u_complementSecond = false;
uniform float u_epsilon;
vec4 iteration() { return vec4(u_k, u_step, u_complementSecond ? 1.0 : 0.0, u_epsilon); }
vec2 invSize() { return 1.0 / vec2(textureSize(u_prev1, 0)); }
ivec2 stateLast() { return textureSize(u_prev1, 0) - 1; }
#else
flat in vec4 v_iteration;
flat in vec2 v_invSize;
flat in ivec2 v_stateLast;
vec4 iteration() { return v_iteration; }
vec2 invSize() { return v_invSize; }
ivec2 stateLast() { return v_stateLast; }
#endif
bool complementSecond() { return iteration().z > 0.5; }

#ifdef COUNT
layout(binding = COUNTER_CHANGED, offset = 0) uniform atomic_uint u_changed;
#endif

#ifndef RESET // the iteration (a restart's programs use these image units for other targets)
layout(binding = IMAGE_HERE1, r32f) uniform readonly image2D u_here1; // p1 again: its texel at the pixel
layout(binding = IMAGE_HERE2, r32f) uniform readonly image2D u_here2; // p2
#ifdef THIRD
layout(binding = IMAGE_HERE3, r32f) uniform readonly image2D u_here3; // p3
#endif
#ifdef THIRD
// .xy as u_vectors below, .z the third population's direction (snorm16 v3.xy): one fetch for all three.
layout(binding = IMAGE_VECTORS, rgba32ui) uniform readonly uimage2D u_vectors;
#else
// v1.xy, v2.xy (max-norm 1) and beta, packed by packVectors (common/projection_pixel.glsl)
layout(binding = IMAGE_VECTORS, rg32ui) uniform readonly uimage2D u_vectors;
#endif

// The mean of p at x + d and x - d, with p_i(x) standing in for a blocked sample.
float advect(sampler2D prev, vec2 x, vec2 d, vec2 inv, float here) {
  float a = texture(prev, (x + d) * inv).r, b = texture(prev, (x - d) * inv).r;
  return 0.5 * ((a < 0.0 ? here : a) + (b < 0.0 ? here : b));
}

#ifdef INTEGER_STEP
// The two texels (offsets a, b from the pixel) a sample at offset d falls between, d's larger component a
// whole number, and b's weight w: the sample is mix(p(a), p(b), w). A zero d gives the pixel itself.
void axisFootprint(vec2 d, out ivec2 a, out ivec2 b, out float w) {
  bool xMajor = abs(d.x) >= abs(d.y);
  float minor = xMajor ? d.y : d.x, major = xMajor ? d.x : d.y;
  float lo = floor(minor);
  w = minor - lo;
  a = xMajor ? ivec2(int(major), int(lo)) : ivec2(int(lo), int(major));
  b = a + (xMajor ? ivec2(0, 1) : ivec2(1, 0));
}
// The mean of the state image IMG at p + d and p - d (as advect), its offsets clamped to the target as the
// samplers clamp to its edge; one function per image. Each sample has its own footprint, so negating d
// swaps the two exactly.
#define DEFINE_ADVECT_AXIS(NAME, SAMPLE, IMG)                                                               \
  float SAMPLE(ivec2 p, vec2 d, ivec2 last) {                                                               \
    ivec2 a, b;                                                                                             \
    float w;                                                                                                \
    axisFootprint(d, a, b, w);                                                                              \
    return mix(imageLoad(IMG, clamp(p + a, ivec2(0), last)).r, imageLoad(IMG, clamp(p + b, ivec2(0), last)).r, w); \
  }                                                                                                         \
  float NAME(ivec2 p, vec2 d, float here) {                                                                 \
    ivec2 last = stateLast();                                                                               \
    float s = SAMPLE(p, d, last), t = SAMPLE(p, -d, last);                                                  \
    return 0.5 * ((s < 0.0 ? here : s) + (t < 0.0 ? here : t));                                             \
  }
DEFINE_ADVECT_AXIS(advectAxis1, axisSample1, u_here1)
DEFINE_ADVECT_AXIS(advectAxis2, axisSample2, u_here2)
#ifdef THIRD
DEFINE_ADVECT_AXIS(advectAxis3, axisSample3, u_here3)
#endif
#endif

// Pixel p's state `here` (p1, p2, p3; p3 0 without THIRD) and its next iterate `next`; false where p is
// blocked (its state stays). With COUNT the pixel is counted when it changed by more than epsilon. `beta`:
// the pixel's mapped noise as the vectors texel holds it (unorm12).
bool advectionStep(ivec2 p, out vec3 next, out vec3 here, out float beta) {
  vec2 s = vec2(imageLoad(u_here1, p).r, imageLoad(u_here2, p).r);
  vec4 it = iteration();
  float k = it.x, stepPixels = it.y;
  vec2 inv = invSize();
  vec2 x = vec2(p) + 0.5;
#ifdef THIRD
  uvec4 q4 = imageLoad(u_vectors, p);
  uvec2 q = q4.xy;
#else
  uvec2 q = imageLoad(u_vectors, p).xy;
#endif
  int packed2 = int(q.y);
  vec2 v2 = vec2(bitfieldExtract(packed2, 0, 10), bitfieldExtract(packed2, 10, 10)) / 511.0;
  vec4 v = vec4(unpackSnorm2x16(q.x), v2) * stepPixels;
  beta = float(q.y >> 20) / 4095.0;
  // A zero vector (no direction) averages p_i(x) with itself.
#ifdef INTEGER_STEP
  vec2 avg = vec2(advectAxis1(p, v.xy, s.r), advectAxis2(p, v.zw, s.g));
#else
  vec2 avg = vec2(advect(u_prev1, x, v.xy, inv, s.r), advect(u_prev2, x, v.zw, inv, s.g));
#endif
  vec2 next2 = k * vec2(beta, complementSecond() ? 1.0 - beta : beta) + (1.0 - k) * avg;
  bool blocked = s.r < 0.0;
#ifdef THIRD
  float s3 = imageLoad(u_here3, p).r;
  vec2 v3 = unpackSnorm2x16(q4.z) * stepPixels;
#ifdef INTEGER_STEP
  float next3 = k * beta + (1.0 - k) * advectAxis3(p, v3, s3);
#else
  float next3 = k * beta + (1.0 - k) * advect(u_prev3, x, v3, inv, s3);
#endif
#else
  float s3 = 0.0, next3 = 0.0;
#endif
#ifdef COUNT
#ifdef THIRD
  bool changed3 = abs(next3 - s3) > it.w;
#else
  bool changed3 = false;
#endif
  bool changed = changed3 || any(greaterThan(abs(next2 - s), vec2(it.w)));
  if (!blocked && changed) atomicCounterIncrement(u_changed);
#endif
  here = vec3(s, s3);
  next = vec3(next2, next3);
  return !blocked;
}
#endif
