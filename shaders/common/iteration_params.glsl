// SPDX-License-Identifier: GPL-3.0-or-later
// The vertex side of an advection iteration's parameters (common/advection_step.glsl): the uniforms read
// once per vertex and handed on flat (on llvmpipe a fragment shader pays for each read of a uniform
// component on every block of pixels, about four times what a flat input costs). Used by the iteration's
// own pass (fabric/advection.vert) and by the composite that runs a frame's last iteration (ADVECT,
// fabric/composite.vert).
layout(binding = UNIT_PREV1) uniform sampler2D u_prev1; // an iteration's p1: the state targets' size
uniform float u_k;
uniform float u_step;
uniform bool u_complementSecond = false;
uniform float u_epsilon;

flat out vec4 v_iteration; // k, step, complement (1 or 0), epsilon (common/advection_step.glsl)
flat out vec2 v_invSize;   // 1 / the state targets' size in texels
flat out ivec2 v_stateLast; // the state targets' last pixel

void handOnIteration() {
  v_iteration = vec4(u_k, u_step, u_complementSecond ? 1.0 : 0.0, u_epsilon);
  v_invSize = 1.0 / vec2(textureSize(u_prev1, 0));
  v_stateLast = textureSize(u_prev1, 0) - 1;
}
