#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Projection pass, geometry stage: rasterises the surface into the guarded target and hands the
// fragment stage the world normal and the linear eye depth (the only per-pixel surface data the
// fullscreen stage needs; it rebuilds the position from the depth).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_viewProj; // world -> clip of the guarded target
uniform mat4 u_view;     // world -> eye

out vec3 v_normal;
out float v_depth;

void main() {
  v_normal = a_normal;
  v_depth = -(u_view * vec4(a_position, 1.0)).z;
  gl_Position = u_viewProj * vec4(a_position, 1.0);
}
