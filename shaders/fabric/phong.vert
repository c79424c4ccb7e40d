#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Plain Blinn-Phong rendering of a mesh: the reference the fabric is benchmarked against.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_viewProj;
uniform mat4 u_view;
uniform mat3 u_viewRot;
out vec3 v_normalEye;
out vec3 v_eye;
void main() {
  v_normalEye = u_viewRot * a_normal;
  v_eye = (u_view * vec4(a_position, 1.0)).xyz;
  gl_Position = u_viewProj * vec4(a_position, 1.0);
}
