#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The tensor stage's vertex shader (fabric/projection.frag): the deferred triangle
// (common/deferred_triangle.glsl) and the stage's parameters handed on flat (common/projection_params.glsl).
#define FORWARD_PARAMS
#include "common/deferred_triangle.glsl"
#include "common/projection_params.glsl"

void main() {
  deferredTriangle();
  forwardParams();
}
