#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/lighting.glsl"
in vec3 v_normalEye;
in vec3 v_eye;
uniform bool u_orthographic;
uniform vec3 u_colour = vec3(0.8, 0.8, 0.78);
uniform float u_ambient = 0.25; // Blinn-Phong material, as the fabric's (common/projection_params.glsl)
uniform float u_diffuse = 0.65;
uniform float u_specular = 0.35;
out vec4 o_colour;
void main() {
  vec3 n = normalize(v_normalEye);
  if (any(isnan(n))) n = vec3(0.0, 0.0, 1.0);
  vec3 toEye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v_eye);
  if (dot(n, toEye) < 0.0) n = -n;
  o_colour = vec4(u_colour * blinnPhong(n, toEye, vec3(u_ambient, u_diffuse, u_specular)), 1.0);
}
