#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry stage of the projection, from a mesh: one RG32UI texel per covered pixel: the interpolated world
// normal, octahedral-encoded as two snorm16 (about 1e-4 rad), and the linear eye depth in mm as float bits.
// The target is cleared to 0, so depth 0 means "no surface here". The shader is trivial on purpose: on a software rasteriser each small triangle costs a full block of fragment
// invocations, so the expensive per-pixel work runs once per pixel in the fullscreen stage instead.
#include "common/octahedral.glsl"

in vec3 v_normal;
in float v_depth;

layout(location = 0) out uvec2 o_geometry;

void main() {
  vec3 n = dot(v_normal, v_normal) > 0.0 ? v_normal : vec3(0.0, 0.0, 1.0);
  o_geometry = uvec2(packSnorm2x16(octahedral(n)), floatBitsToUint(max(v_depth, 1e-6)));
}
