// Sampling the fibre set uploaded by GpuFibreSet: up to three RGBA32F 3D textures, one per slot of
// continuousSlots (io/model/fibre_set.h): amplitude x unit world direction and the amplitude, with the
// lobes already matched between neighbouring voxels by |cos| and sign-aligned on the CPU, so the hardware
// interpolates them per component; an RGBA32F texture holds the paired tensor's FA (or 1), 1 where a voxel
// has fibres and that occupancy blurred by [1 2 1] / 4 per axis (the data's smooth edge: fibreEdge). The
// rule, interpolateSlots in io/model/fibre_set.h being its CPU reference:
//   * nothing where less than half of the trilinear weight lies on voxels with fibres (sampleFibres'
//     minWeight 0.5; the renderer decodes a little beyond, 0.02, and draws the edge from fibreEdge);
//   * per slot: amplitude = interpolated amplitude / that weight; direction = the normalised interpolated
//     vector, or the nearest voxel's direction where the vector is shorter than 0.9 x the interpolated
//     amplitude (a sign seam or a disagreement between voxels).

layout(binding = UNIT_LOBE0) uniform sampler3D u_lobe0;
layout(binding = UNIT_LOBE1) uniform sampler3D u_lobe1;
layout(binding = UNIT_LOBE2) uniform sampler3D u_lobe2;
layout(binding = UNIT_FIBRE_FA) uniform sampler3D u_fibreFa; // FA (or 1), 1 where the voxel has fibres, blurred
// u_worldToTex, u_lobeCount (1..3 slots uploaded): common/projection_params.glsl

// One slot at texture coordinate tc: its direction and amplitude (amp 0 = none) by the rule above. A
// function of the sampler, called once per slot: a slot chosen by a runtime index would make a software
// rasteriser sample every slot's texture for each slot (its branches run masked, not skipped).
void sampleSlot(sampler3D lobe, vec3 tc, ivec3 nearest, float occupancy, inout int n, out vec3 dir, out float amp) {
  dir = vec3(0.0);
  amp = 0.0;
  vec4 a = texture(lobe, tc);
  if (a.w <= 0.0) return;
  float len = length(a.xyz);
  vec3 d = len > 0.0 ? a.xyz / len : vec3(0.0);
  if (len < 0.9 * a.w) {
    vec4 q = texelFetch(lobe, nearest, 0);
    if (q.w > 0.0) d = q.xyz / q.w;
  }
  if (dot(d, d) == 0.0) return;
  dir = normalize(d);
  amp = a.w / occupancy;
  ++n;
}

// Up to three fibres at worldPos in slot order (amp 0 = none; a slot follows one bundle from voxel to voxel,
// so slot j feeds advection field j) where at least minWeight of the trilinear weight lies on voxels with
// fibres; returns their number. fa: the paired tensor's FA (trilinear) or 1.
int sampleFibres(vec3 worldPos, float minWeight, out vec3 dir[3], out float amp[3], out float fa) {
  vec3 tc = (u_worldToTex * vec4(worldPos, 1.0)).xyz;
  for (int j = 0; j < 3; ++j) {
    dir[j] = vec3(0.0);
    amp[j] = 0.0;
  }
  vec2 fo = texture(u_fibreFa, tc).rg;
  fa = 0.0;
  if (!(fo.g >= minWeight)) return 0;
  fa = fo.r / fo.g;
  ivec3 dims = textureSize(u_lobe0, 0);
  ivec3 nearest = clamp(ivec3(floor(tc * vec3(dims))), ivec3(0), dims - 1);
  int n = 0;
  if (u_lobeCount > 0) sampleSlot(u_lobe0, tc, nearest, fo.g, n, dir[0], amp[0]);
  if (u_lobeCount > 1) sampleSlot(u_lobe1, tc, nearest, fo.g, n, dir[1], amp[1]);
  if (u_lobeCount > 2) sampleSlot(u_lobe2, tc, nearest, fo.g, n, dir[2], amp[2]);
  return n;
}

// The data's edge field at worldPos: its 0.5 contour is the fibre set's smooth outline.
float fibreEdge(vec3 worldPos) {
  return texture(u_fibreFa, (u_worldToTex * vec4(worldPos, 1.0)).xyz).b;
}
