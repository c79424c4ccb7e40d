#version 450 core
// The fullscreen triangle (common/fullscreen_triangle.glsl) of the image passes without parameters of their
// own.
#include "common/fullscreen_triangle.glsl"

void main() { fullscreenTriangle(); }
