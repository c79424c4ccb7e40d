#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The fullscreen triangle (common/fullscreen_triangle.glsl) of the image passes without parameters of their
// own.
#include "common/fullscreen_triangle.glsl"

void main() { fullscreenTriangle(); }
