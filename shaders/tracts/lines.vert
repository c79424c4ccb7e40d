#version 450 core
// Tract overlay: world RAS positions of the (display-decimated) polyline points, drawn as line strips.
layout(location = 0) in vec3 a_position;
uniform vec4 u_plane; // slab plane (unit normal, offset): signed distance = dot(n, p) + w, mm
out vec3 v_world;
out float v_planeDist;
void main() {
  v_world = a_position;
  v_planeDist = dot(u_plane.xyz, a_position) + u_plane.w;
  gl_Position = vec4(a_position, 1.0);
}
