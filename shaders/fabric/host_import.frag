#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry stage of the projection, from a host: writes the same geometry buffers as fabric/geometry.*
// (octahedral world normal and linear eye depth per pixel, window depth) from the host's depth texture and
// world-normal texture, once per pixel of the guarded target. A pixel inside the host's viewport takes the
// host texel it covers; its window depth is the host's value unchanged, so the composite writes exactly the
// depth the host's surface has. A pixel of the guard border (outside the viewport, where the host has no
// data) continues the surface: the tangent plane of the nearest viewport pixel, cut by the pixel's ray (an
// approximation: exact for planes, close for smooth surfaces over the few pixels of the border), so the
// threads do not fray and no silhouette appears at the viewport's edge. No surface: the host's depth at the
// far plane (window depth 1) or a zero normal.
#include "common/octahedral.glsl"
#include "common/texel.glsl"

noperspective in vec3 v_nearEye; // the pixel's ray in eye space (common/deferred_triangle.glsl)
noperspective in vec3 v_farEye;

layout(binding = UNIT_HOST_DEPTH) uniform sampler2D u_hostDepth; // window depth in [0, 1]
layout(binding = UNIT_HOST_NORMAL) uniform sampler2D u_hostNormal; // world normal (any length), see u_biasedNormals
// The import's parameters: the uniforms of fabric/host_import.vert (described there), received as its flat
// outputs under the uniforms' names.
flat in ivec4 v_viewport;
flat in ivec2 v_guardBiased;
flat in mat4 v_hostClipToEye;
flat in mat3 v_viewRot;
flat in mat4 v_projection;
#define u_origin (v_viewport.xy)
#define u_extent (v_viewport.zw)
#define u_guard (v_guardBiased.x)
#define u_biasedNormals (v_guardBiased.y != 0)
#define u_hostClipToEye v_hostClipToEye
#define u_viewRot v_viewRot
#define u_projection v_projection

layout(location = 0) out uvec2 o_geometry;

// The eye position of host pixel q at window depth d.
vec3 eyeAt(ivec2 q, float d) {
  vec2 ndc = (vec2(q - u_origin) + 0.5) / vec2(u_extent) * 2.0 - 1.0;
  vec4 e = u_hostClipToEye * vec4(ndc, 2.0 * d - 1.0, 1.0);
  return e.xyz / e.w;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) - u_guard; // pixel in the viewport
  ivec2 q = clamp(p, ivec2(0), u_extent - 1) + u_origin;
  float d = texel(u_hostDepth, q).r;
  if (d >= 1.0) discard; // the background costs one fetch
  vec3 n = texel(u_hostNormal, q).xyz;
  if (u_biasedNormals) n = n * 2.0 - 1.0;
  if (dot(n, n) < 1e-12) discard;
  n = normalize(n);
  vec3 eye = eyeAt(q, d);
  float depth = -eye.z;
  float window = d;
  if (q != p + u_origin) {
    // Guard border: the pixel's ray cut with the tangent plane at the nearest viewport pixel.
    vec3 nEye = u_viewRot * n;
    vec3 ray = v_farEye - v_nearEye;
    float den = dot(nEye, ray);
    if (abs(den) < 1e-6 * length(ray)) discard;
    float s = dot(nEye, eye - v_nearEye) / den;
    if (s <= 0.0 || s >= 1.0) discard;
    vec3 x = v_nearEye + s * ray;
    depth = -x.z;
    vec4 c = u_projection * vec4(x, 1.0);
    window = clamp(0.5 * c.z / c.w + 0.5, 0.0, 0.99999);
  }
  if (!(depth > 0.0)) discard;
  o_geometry = uvec2(packSnorm2x16(octahedral(n)), floatBitsToUint(max(depth, 1e-6)));
  gl_FragDepth = window;
}
