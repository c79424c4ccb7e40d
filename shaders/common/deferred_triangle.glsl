// SPDX-License-Identifier: GPL-3.0-or-later
// One triangle covering the target at the far plane (window depth 1), for passes that run once per
// covered pixel: with the surface's depth buffer attached and GL_GREATER, the early depth test rejects
// the background, and blocks of pixels without surface are skipped before shading. Also hands the
// fragment stage the eye-space points of the pixel's ray on the near and far clip planes (affine in
// screen space for both projections), from which it rebuilds the eye position at a given depth.
uniform mat4 u_clipToEye; // inverse projection of the guarded target

noperspective out vec3 v_nearEye;
noperspective out vec3 v_farEye;

void deferredTriangle() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  vec4 n = u_clipToEye * vec4(p, -1.0, 1.0);
  vec4 f = u_clipToEye * vec4(p, 1.0, 1.0);
  v_nearEye = n.xyz / n.w;
  v_farEye = f.xyz / f.w;
  gl_Position = vec4(p, 1.0, 1.0);
}
