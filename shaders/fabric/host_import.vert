#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The host import's vertex shader (fabric/host_import.frag): the deferred triangle
// (common/deferred_triangle.glsl) and the import's parameters handed on as flat outputs, read here three
// times a draw (on llvmpipe a fragment shader pays for each read of a uniform component on every block of
// pixels, about four times what a flat input costs).
#include "common/deferred_triangle.glsl"

uniform bool u_biasedNormals;  // the texture holds 0.5 n + 0.5 (unsigned normalised formats)
uniform ivec2 u_origin;        // the viewport's lower-left pixel in the host textures
uniform ivec2 u_extent;        // the viewport's size in pixels
uniform int u_guard;           // guard border of the target, pixels
uniform mat4 u_hostClipToEye;  // inverse of the host's projection
uniform mat3 u_viewRot;        // world -> eye rotation (normals)
uniform mat4 u_projection;     // the host's projection (window depth of guard pixels)

flat out ivec4 v_viewport;     // origin, extent
flat out ivec2 v_guardBiased;  // guard, biased normals (1 or 0)
flat out mat4 v_hostClipToEye;
flat out mat3 v_viewRot;
flat out mat4 v_projection;

void main() {
  deferredTriangle();
  v_viewport = ivec4(u_origin, u_extent);
  v_guardBiased = ivec2(u_guard, u_biasedNormals ? 1 : 0);
  v_hostClipToEye = u_hostClipToEye;
  v_viewRot = u_viewRot;
  v_projection = u_projection;
}
