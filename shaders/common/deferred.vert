#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The deferred triangle of passes without parameters of their own (common/deferred_triangle.glsl).
#include "common/deferred_triangle.glsl"

void main() { deferredTriangle(); }
