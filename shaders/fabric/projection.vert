#version 450 core
// Projection pass, vertex stage: world RAS mm positions and normals through the camera (with the guard
// border folded into u_viewProj).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

uniform mat4 u_viewProj; // world -> clip of the guarded target
uniform mat4 u_view;     // world -> eye

// Invariant: the depth pre-pass and the projection pass must produce bit-identical depths.
invariant gl_Position;

out vec3 v_world;
out vec3 v_normal;
out vec3 v_eye;

void main() {
  v_world = a_position;
  v_normal = a_normal;
  v_eye = (u_view * vec4(a_position, 1.0)).xyz;
  gl_Position = u_viewProj * vec4(a_position, 1.0);
}
