#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Tract overlay: world RAS positions of the (display-decimated) polyline points, drawn as line strips.
layout(location = 0) in vec3 a_position;
uniform vec4 u_plane; // slab plane (unit normal, offset): signed distance = dot(n, p) + w, mm
layout(location = 1) in vec4 a_colour; // alpha 1: this colour; alpha 0: DEC of the tangent
layout(location = 2) in float a_node;  // node along the profiled bundle; < 0: none
out vec3 v_world;
out float v_node;
out vec4 v_colour;
out float v_planeDist;
void main() {
  v_world = a_position;
  v_colour = a_colour;
  v_node = a_node;
  v_planeDist = dot(u_plane.xyz, a_position) + u_plane.w;
  gl_Position = vec4(a_position, 1.0);
}
