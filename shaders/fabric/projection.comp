#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The tensor stage of fabric/projection.frag as a compute shader (the same common/projection_pixel.glsl), for
// GPUs whose fragment pipeline is the narrow part of the chip (TensorStage::setCompute). One invocation per
// pixel of the target, in 8x8 work groups:
// - covered pixels (the geometry stage's window depth below 1, where the fragment pass's early depth test
//   passes) are projected and written; the others get the surface target's cleared value (0: uncovered) and
//   keep the rest, as the fragment pass leaves them;
// - the ray's eye points on the near and far planes come from u_clipToEye at the pixel centre, as
//   common/deferred.vert's varyings interpolate them;
// - the cover ramp's screen-space width of the edge field comes from the work group's 2x2 quads (shared
//   memory), as a fragment shader's fwidth does, so every pixel computes its edge value first;
// - the covered pixels are counted (per work group, then one atomic add), for coveredPixels().
layout(local_size_x = 8, local_size_y = 8) in;
#define COMPUTE
#include "common/projection_pixel.glsl"

uniform mat4 u_clipToEye; // inverse projection of the guarded target
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth; // the geometry stage's window depth (1: no surface)
layout(binding = IMAGE_VECTORS, rg32ui) uniform writeonly uimage2D i_vectors;
layout(binding = IMAGE_SURFACE, rgba32f) uniform writeonly image2D i_surface;
layout(binding = IMAGE_EIGEN, rgba8) uniform writeonly image2D i_eigen;
layout(binding = IMAGE_LAMBDA, rgba8) uniform writeonly image2D i_lambda;
layout(binding = IMAGE_LIGHT, r16) uniform writeonly image2D i_light;
#ifdef FIBRES
layout(binding = IMAGE_FIBRES, rgba32ui) uniform writeonly uimage2D i_fibres;
layout(binding = IMAGE_VECTORS3, rgba32ui) uniform writeonly uimage2D i_vectors3;
#endif
layout(std430, binding = BUFFER_COVERED) buffer CoveredPixels { uint u_coveredPixels; };

shared float s_edge[64];
shared uint s_covered;

void main() {
  ivec2 size = imageSize(i_surface);
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  bool inside = all(lessThan(px, size));
  ivec2 q = min(px, size - 1);
  vec2 ndc = (vec2(q) + 0.5) / vec2(size) * 2.0 - 1.0;
  vec4 n = u_clipToEye * vec4(ndc, -1.0, 1.0);
  vec4 f = u_clipToEye * vec4(ndc, 1.0, 1.0);
  float edge;
  Projection p = projectPixel(q, n.xyz / n.w, f.xyz / f.w, edge);
  uvec2 l = gl_LocalInvocationID.xy;
  if (gl_LocalInvocationIndex == 0u) s_covered = 0u;
  s_edge[l.y * 8u + l.x] = edge;
  memoryBarrierShared(); // the writes to shared memory visible to the work group (with the barrier)
  barrier();
  float dx = s_edge[l.y * 8u + (l.x | 1u)] - s_edge[l.y * 8u + (l.x & ~1u)];
  float dy = s_edge[(l.y | 1u) * 8u + l.x] - s_edge[(l.y & ~1u) * 8u + l.x];
  if (inside && texelFetch(u_depth, q, 0).r < 1.0) {
    p.lambda.w *= coverRamp(edge, abs(dx) + abs(dy));
    imageStore(i_vectors, px, uvec4(p.vectors, 0u, 0u));
    imageStore(i_surface, px, p.surface);
    imageStore(i_eigen, px, p.eigen);
    imageStore(i_lambda, px, p.lambda);
    imageStore(i_light, px, vec4(p.surface.g));
#ifdef FIBRES
    imageStore(i_fibres, px, uvec4(p.fibres.xyz, fibreAttributes(p)));
    imageStore(i_vectors3, px, p.vectors3);
#endif
    atomicAdd(s_covered, 1u);
  } else if (inside) {
    imageStore(i_surface, px, vec4(0.0));
  }
  memoryBarrierShared();
  barrier();
  if (gl_LocalInvocationIndex == 0u && s_covered > 0u) atomicAdd(u_coveredPixels, s_covered);
}
