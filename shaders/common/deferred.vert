#version 450 core
// The deferred triangle of passes without parameters of their own (common/deferred_triangle.glsl).
#include "common/deferred_triangle.glsl"

void main() { deferredTriangle(); }
