// Sampling the fibre set uploaded by GpuFibreSet: up to three RGBA32F 3D textures (unit world direction,
// amplitude; nearest) and an R32F FA texture. Directions cannot be interpolated per component (no sign,
// peak order differs between voxels), so the 8 voxels around the point are gathered and matched here, the
// same rule as interpolateFibres (io/model/fibre_set.h, without sorting), its CPU reference:
//   * in each voxel, lobes below u_relThreshold x that voxel's strongest are dropped;
//   * the voxel with the largest trilinear weight among those with fibres is the reference;
//   * each reference lobe takes from every other voxel the lobe with the largest |cos| to it (when
//     |cos| >= u_minMatchCos and no other reference lobe is closer to that lobe), sign-aligned, weighted by
//     trilinear weight x amplitude;
//   * direction = normalised weighted sum, amplitude = weighted sum / weight of the voxels with fibres;
//   * nothing where less than half of the weight lies on voxels with fibres.

layout(binding = 0) uniform sampler3D u_lobe0;
layout(binding = 1) uniform sampler3D u_lobe1;
layout(binding = 5) uniform sampler3D u_lobe2;
layout(binding = 6) uniform sampler3D u_fibreFa;
uniform mat4 u_worldToTex;
uniform int u_lobeCount = 1;          // 1..3 slots uploaded
uniform float u_relThreshold = 0.15;  // relative amplitude threshold per voxel
uniform float u_minMatchCos = 0.5;    // lobes further than 60 degrees from a reference lobe do not match

vec4 fetchLobe(int l, ivec3 p) {
  if (l == 0) return texelFetch(u_lobe0, p, 0);
  if (l == 1) return texelFetch(u_lobe1, p, 0);
  return texelFetch(u_lobe2, p, 0);
}

// Up to three fibres at worldPos in the reference voxel's slot order (amp 0 = none; GpuFibreSet uploads
// slots that hold the same bundle from voxel to voxel, so slot j feeds advection field j); returns their
// number. fa: the paired tensor's FA (trilinear) or 1.
int sampleFibres(vec3 worldPos, out vec3 dir[3], out float amp[3], out float fa) {
  vec3 tc = (u_worldToTex * vec4(worldPos, 1.0)).xyz;
  ivec3 dims = textureSize(u_lobe0, 0);
  vec3 v = tc * vec3(dims) - 0.5;
  ivec3 b = ivec3(floor(v));
  vec3 f = v - vec3(b);
  vec4 lobes[8][3];
  float w[8];
  bool has[8];
  float valid = 0.0;
  int ref = -1;
  for (int c = 0; c < 8; ++c) {
    ivec3 o = ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    ivec3 p = b + o;
    vec3 t = mix(1.0 - f, f, vec3(o));
    w[c] = t.x * t.y * t.z;
    has[c] = false;
    bool inside = all(greaterThanEqual(p, ivec3(0))) && all(lessThan(p, dims));
    for (int l = 0; l < 3; ++l) lobes[c][l] = vec4(0.0);
    if (!inside) continue;
    float top = 0.0;
    for (int l = 0; l < 3; ++l) {
      if (l >= u_lobeCount) break;
      lobes[c][l] = fetchLobe(l, p);
      top = max(top, lobes[c][l].w);
    }
    for (int l = 0; l < 3; ++l) {
      if (lobes[c][l].w > 0.0 && lobes[c][l].w >= u_relThreshold * top)
        has[c] = true;
      else
        lobes[c][l] = vec4(0.0);
    }
    if (!has[c]) continue;
    valid += w[c];
    if (ref < 0 || w[c] > w[ref]) ref = c;
  }
  for (int j = 0; j < 3; ++j) {
    dir[j] = vec3(0.0);
    amp[j] = 0.0;
  }
  fa = 0.0;
  if (ref < 0 || valid < 0.5) return 0;
  fa = texture(u_fibreFa, tc).r;
  int n = 0;
  for (int j = 0; j < 3; ++j) {
    vec4 r = lobes[ref][j];
    if (r.w <= 0.0) continue;
    vec3 acc = w[ref] * r.w * r.xyz;
    float a = w[ref] * r.w;
    for (int c = 0; c < 8; ++c) {
      if (c == ref || !has[c]) continue;
      float bestCos = 0.0, bestAbs = -1.0;
      vec4 best = vec4(0.0);
      for (int l = 0; l < 3; ++l) {
        vec4 q = lobes[c][l];
        if (q.w <= 0.0) continue;
        float d = dot(q.xyz, r.xyz);
        if (abs(d) > bestAbs) {
          bestAbs = abs(d);
          bestCos = d;
          best = q;
        }
      }
      if (bestAbs < u_minMatchCos) continue;
      // Mutual best only: a lobe closer to another reference lobe belongs to that one.
      bool mutual = true;
      for (int j2 = 0; j2 < 3; ++j2)
        if (j2 != j && lobes[ref][j2].w > 0.0 && abs(dot(lobes[ref][j2].xyz, best.xyz)) > bestAbs) mutual = false;
      if (!mutual) continue;
      acc += w[c] * best.w * (bestCos < 0.0 ? -1.0 : 1.0) * best.xyz;
      a += w[c] * best.w;
    }
    float len = length(acc);
    if (len <= 0.0) continue;
    dir[j] = acc / len;
    amp[j] = a / valid;
    ++n;
  }
  return n;
}
