#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The advection pass's vertex shader (fabric/advection.frag): the fullscreen triangle, and the iteration's
// parameters handed on as flat outputs. On llvmpipe a fragment shader pays for each read of a uniform
// component on every block of pixels, about four times what a flat input costs; here they are read three
// times a draw. The compute twin (fabric/advection.comp) reads the same uniforms itself.
#include "common/fullscreen_triangle.glsl"
#include "common/iteration_params.glsl"

layout(binding = UNIT_SURFACE) uniform sampler2D u_surface; // a restart's surface target: its size
uniform float u_threshold;  // RESET SILHOUETTES: mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background; // RESET SILHOUETTES: linear depth assigned to empty pixels
#ifdef REPROJECT
uniform mat4 u_windowToWorld;     // (pixel x, y, window depth, 1) of this frame -> world
uniform mat4 u_worldToPrevWindow; // world -> previous frame's (pixel x, y)
uniform mat4 u_worldToPrevEye;    // world -> previous frame's eye space
uniform float u_depthTol;         // mm
flat out mat4 v_windowToWorld;
flat out mat4 v_worldToPrevWindow;
flat out mat4 v_worldToPrevEye;
flat out float v_depthTol;
#endif

flat out vec2 v_silhouette; // threshold, background (common/advection_restart.glsl)
flat out ivec2 v_surfaceLast; // the surface target's last pixel (common/advection_restart.glsl)

void main() {
  fullscreenTriangle();
  handOnIteration();
  v_silhouette = vec2(u_threshold, u_background);
  v_surfaceLast = textureSize(u_surface, 0) - 1;
#ifdef REPROJECT
  v_windowToWorld = u_windowToWorld;
  v_worldToPrevWindow = u_worldToPrevWindow;
  v_worldToPrevEye = u_worldToPrevEye;
  v_depthTol = u_depthTol;
#endif
}
