// SPDX-License-Identifier: GPL-3.0-or-later
// One triangle covering the viewport; the image passes address their inputs with gl_FragCoord. With
// FAR_PLANE it lies at window depth 1: drawn with the surface's depth buffer attached and GL_GREATER, the
// early depth test then rejects the background, so blocks of pixels without surface are never shaded.
void fullscreenTriangle() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
#ifdef FAR_PLANE
  gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
#else
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
#endif
}
