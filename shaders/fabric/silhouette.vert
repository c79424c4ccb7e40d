#version 450 core
// The silhouette pass's vertex shader (fabric/silhouette.frag): the fullscreen triangle, and the threshold
// and background depth handed on as a flat output (see fabric/advection.vert for why).
#include "common/fullscreen_triangle.glsl"

uniform float u_threshold;   // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background;  // linear depth assigned to empty pixels (beyond the far side of the scene)

flat out vec2 v_silhouette;  // threshold, background

void main() {
  fullscreenTriangle();
  v_silhouette = vec2(u_threshold, u_background);
}
