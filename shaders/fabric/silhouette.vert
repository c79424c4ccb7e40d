#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The silhouette pass's vertex shader (fabric/silhouette.frag): the fullscreen triangle, and the threshold
// and background depth handed on as a flat output (see fabric/advection.vert for why).
#include "common/fullscreen_triangle.glsl"

layout(binding = UNIT_SURFACE) uniform sampler2D u_surface; // the surface target: its size
uniform float u_threshold;   // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background;  // linear depth assigned to empty pixels (beyond the far side of the scene)

flat out vec2 v_silhouette;  // threshold, background
flat out ivec2 v_surfaceLast; // the surface target's last pixel

void main() {
  fullscreenTriangle();
  v_silhouette = vec2(u_threshold, u_background);
  v_surfaceLast = textureSize(u_surface, 0) - 1;
}
