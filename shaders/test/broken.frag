#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Test fixture: a deliberate compile error on line 7, after an include, so the tests can check that
// ShaderProgram maps the error back to this file and line.
#include "common/eigen.glsl"
out vec4 o_colour;
void main() { o_colour = vec4(undefinedThing); }
