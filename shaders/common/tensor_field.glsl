// SPDX-License-Identifier: GPL-3.0-or-later
// Sampling the tensor field uploaded by GpuTensorField: two RGBA32F 3D textures holding
// (xx, xy, xz, yy) and (yz, zz, FA, valid) per voxel, world RAS mm -> texture coordinates by
// u_worldToTex. The tensor is interpolated component-wise by the hardware (never its eigenvectors), and
// renormalised by the interpolated validity so invalid (zero) voxels do not shrink their neighbours.

layout(binding = UNIT_TENSOR_A) uniform sampler3D u_tensorA;
layout(binding = UNIT_TENSOR_B) uniform sampler3D u_tensorB;
layout(binding = UNIT_TENSOR_EDGE) uniform sampler3D u_tensorEdge; // the mask, blurred (GpuTensorField)
// u_worldToTex: common/projection_params.glsl

// The interpolated validity `valid` (the trilinear data mask, 0..1) and, where it is at least minValid, the
// tensor renormalised by it. False where valid < minValid (outside the data: t = 0, fa = 0).
bool sampleTensorValid(vec3 worldPos, float minValid, out mat3 t, out float fa, out float valid) {
  vec3 tc = (u_worldToTex * vec4(worldPos, 1.0)).xyz;
  vec4 a = texture(u_tensorA, tc);
  vec4 b = texture(u_tensorB, tc);
  t = mat3(0.0);
  fa = 0.0;
  valid = clamp(b.w, 0.0, 1.0);
  if (!(valid >= minValid) || valid <= 0.0) return false;
  float inv = 1.0 / valid;
  a *= inv;
  b.xyz *= inv;
  // mat3 is column-major; symmetric, so the layout of off-diagonals does not matter.
  t = mat3(a.x, a.y, a.z,
           a.y, a.w, b.x,
           a.z, b.x, b.y);
  fa = clamp(b.z, 0.0, 1.0);
  return true;
}

// The data's edge field at a world point: the blurred mask, trilinear; its 0.5 contour is the smooth outline.
float dataEdge(vec3 worldPos) {
  return texture(u_tensorEdge, (u_worldToTex * vec4(worldPos, 1.0)).xyz).r;
}

// False outside the data or where fewer than half the interpolation weights are valid voxels.
bool sampleTensor(vec3 worldPos, out mat3 t, out float fa) {
  float valid;
  return sampleTensorValid(worldPos, 0.5, t, fa, valid);
}
