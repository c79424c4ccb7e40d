// SPDX-License-Identifier: GPL-3.0-or-later
// Sampling the fibre set uploaded by GpuFibreSet: per slot of continuousSlots (io/model/fibre_set.h) two
// RGBA32F 3D textures holding the amplitude-weighted dyadic a d d^T of its unit world direction d, (xx, xy,
// xz, yy) and (yz, zz, a, 0), interpolated per component by the hardware; an RGBA32F texture holds the paired
// tensor's FA (or 1), 1 where a voxel has fibres and that occupancy blurred by [1 2 1] / 4 per axis (the
// data's smooth edge, sampleFibres' `edge`). The rule, interpolateSlots in io/model/fibre_set.h being its CPU
// reference:
//   * nothing where less than half of the trilinear weight lies on voxels with fibres (sampleFibres'
//     minWeight 0.5; the renderer decodes a little beyond, 0.02, and draws the edge from that field);
//   * per slot: amplitude = interpolated amplitude / that weight; direction = the principal eigenvector of the
//     interpolated dyadic. The dyadic does not change with the sign of d, so where neighbouring voxels
//     disagree (a seam of the slots' sign alignment, noisy directions in grey matter) the direction turns
//     continuously, as an interpolated tensor's does, instead of jumping at a voxel boundary.

layout(binding = UNIT_LOBE0) uniform sampler3D u_lobe0;
layout(binding = UNIT_LOBE1) uniform sampler3D u_lobe1;
layout(binding = UNIT_LOBE2) uniform sampler3D u_lobe2;
layout(binding = UNIT_LOBE0B) uniform sampler3D u_lobe0b;
layout(binding = UNIT_LOBE1B) uniform sampler3D u_lobe1b;
layout(binding = UNIT_LOBE2B) uniform sampler3D u_lobe2b;
layout(binding = UNIT_FIBRE_FA) uniform sampler3D u_fibreFa; // FA (or 1), 1 where the voxel has fibres, blurred
// u_worldToTex, u_lobeCount (1..3 slots uploaded): common/projection_params.glsl

// One slot at texture coordinate tc: its direction and amplitude (amp 0 = none) by the rule above. A
// function of the samplers, called once per slot: a slot chosen by a runtime index would make a software
// rasteriser sample every slot's texture for each slot (its branches run masked, not skipped).
void sampleSlot(sampler3D lobe, sampler3D lobeB, vec3 tc, float occupancy, inout int n, out vec3 dir,
                out float amp) {
  dir = vec3(0.0);
  amp = 0.0;
  vec4 b = texture(lobeB, tc);
  if (b.z <= 0.0) return;
  vec4 a = texture(lobe, tc);
  dir = principalEigenvector(mat3(a.x, a.y, a.z,
                                  a.y, a.w, b.x,
                                  a.z, b.x, b.y));
  amp = b.z / occupancy;
  ++n;
}

// Up to three fibres at worldPos in slot order (amp 0 = none; a slot follows one bundle from voxel to voxel,
// so slot j feeds advection field j) where at least minWeight of the trilinear weight lies on voxels with
// fibres; returns their number. fa: the paired tensor's FA (trilinear) or 1; edge: the data's edge field
// there (its 0.5 contour is the fibre set's smooth outline), from the same fetch.
int sampleFibres(vec3 worldPos, float minWeight, out vec3 dir[3], out float amp[3], out float fa,
                 out float edge) {
  vec3 tc = (u_worldToTex * vec4(worldPos, 1.0)).xyz;
  for (int j = 0; j < 3; ++j) {
    dir[j] = vec3(0.0);
    amp[j] = 0.0;
  }
  vec3 fo = texture(u_fibreFa, tc).rgb;
  edge = fo.b;
  fa = 0.0;
  if (!(fo.g >= minWeight)) return 0;
  fa = fo.r / fo.g;
  int n = 0;
  if (u_lobeCount > 0) sampleSlot(u_lobe0, u_lobe0b, tc, fo.g, n, dir[0], amp[0]);
  if (u_lobeCount > 1) sampleSlot(u_lobe1, u_lobe1b, tc, fo.g, n, dir[1], amp[1]);
  if (u_lobeCount > 2) sampleSlot(u_lobe2, u_lobe2b, tc, fo.g, n, dir[2], amp[2]);
  return n;
}
