#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Test probe for common/eigen.glsl: decomposes the tensor stored in texels of two RGBA32F textures
// (xx xy xz yy / yz zz - -) and writes eigenvalues and eigenvectors, and the principal eigenvector alone,
// for comparison with the CPU solver.
#include "common/eigen.glsl"
layout(binding = 0) uniform sampler2D u_a;
layout(binding = 1) uniform sampler2D u_b;
layout(location = 0) out vec4 o_values;
layout(location = 1) out vec4 o_v0;
layout(location = 2) out vec4 o_v1;
layout(location = 3) out vec4 o_v2;
layout(location = 4) out vec4 o_principal; // principalEigenvector
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 a = texelFetch(u_a, p, 0), b = texelFetch(u_b, p, 0);
  mat3 t = mat3(a.x, a.y, a.z, a.y, a.w, b.x, a.z, b.x, b.y);
  vec3 vals;
  mat3 vecs;
  eigenDecompose(t, vals, vecs);
  o_values = vec4(vals, 0.0);
  o_v0 = vec4(vecs[0], 0.0);
  o_v1 = vec4(vecs[1], 0.0);
  o_v2 = vec4(vecs[2], 0.0);
  o_principal = vec4(principalEigenvector(t), 0.0);
}
