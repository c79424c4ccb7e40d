#version 450 core
// The fullscreen triangle of the image passes without parameters of their own (common/fullscreen_triangle.glsl).
#include "common/fullscreen_triangle.glsl"

void main() { fullscreenTriangle(); }
