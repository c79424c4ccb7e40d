// SPDX-License-Identifier: GPL-3.0-or-later
// The tensor stage of the projection for one pixel, shared by the fragment pass (fabric/projection.frag)
// and its compute twin (fabric/projection.comp); the comments of fabric/projection.frag describe it.
#include "common/projection_params.glsl"
#include "common/eigen.glsl"
#ifdef FIBRES
#include "common/fibre_field.glsl"
#else
#include "common/tensor_field.glsl"
#endif
#include "common/lighting.glsl"
#include "common/octahedral.glsl"
#ifdef UNCERTAINTY
#include "common/fray.glsl"
layout(binding = UNIT_UNCERTAINTY) uniform sampler3D u_uncertainty; // cone / 90 degrees per slot (rgb), trilinear
#endif

// The geometry stage's target: octahedral normal (snorm16 x2), linear depth bits.
layout(binding = IMAGE_GEOMETRY, rg32ui) uniform readonly uimage2D u_geometry;

layout(binding = UNIT_NOISE) uniform sampler2D u_noise;
#ifdef BACKGROUND
layout(binding = UNIT_BACKGROUND) uniform sampler3D u_background; // grey shown where there is no tensor data
#endif
#ifdef ALONG
// The streamlines' proximity weight (surfaces/analyses/tract_proximity.h): 1 near them, 0 away, 0 outside.
layout(binding = UNIT_ALONG) uniform sampler3D u_along;
#endif

// Image-space direction of world direction v at p: the pixel difference of the projections of p + eps v
// and p (perspective-correct; the clip position of p + eps v is c0 + eps M (v, 0) by linearity), max-norm
// scaled (Eq. 4-5); zero when it degenerates (v along the view ray).
vec2 imageDirection(vec4 c0, vec3 v) {
  vec4 c1 = c0 + u_eps * (u_viewProj * vec4(v, 0.0));
  vec2 d = (c1.xy / c1.w - c0.xy / c0.w) * 0.5 * u_targetSize;
  float m = max(abs(d.x), abs(d.y));
  return m > 1e-4 ? d / m : vec2(0.0);
}

// Mip level of the noise: texels per pixel on the voxel face, from the pixel size at this depth and the
// obliquity of the surface to the view and to the face (no screen-space derivatives needed).
float noiseLod(float depth, float cosView, float cosFace) {
  float pixelMm = u_orthographic ? u_pixelMm : u_pixelMmPerDepth * depth;
  float texelsPerPixel = float(textureSize(u_noise, 0).x) / u_lod * pixelMm / max(cosView * cosFace, 0.05);
  return max(log2(texelsPerPixel), 0.0);
}

float sampleNoise(vec3 p, vec3 n, float lod) {
  vec3 vox = (p - u_noiseOrigin) / u_lod; // Eq. 7
  vec3 an = abs(n);
#ifdef NOISE_BLEND // softened switch between voxel faces (not Eq. 9 exactly)
  float bx = textureLod(u_noise, fract(vox.yz), lod).r;
  float by = textureLod(u_noise, fract(vox.xz), lod).r;
  float bz = textureLod(u_noise, fract(vox.xy), lod).r;
  vec3 w = pow(an, vec3(1.0 / u_noiseBlend));
  return dot(w, vec3(bx, by, bz)) / max(w.x + w.y + w.z, 1e-6);
#endif
  // Eq. 8-9: the two components of frac(vox) spanning the voxel face whose normal is closest to n.
  vec2 t = an.x >= an.y && an.x >= an.z ? vox.yz : (an.y >= an.z ? vox.xz : vox.xy);
  return textureLod(u_noise, fract(t), lod).r;
}

// The advection's whole input in 8 bytes (a software rasteriser's iterations pay for the bytes they read):
// .x v1.xy as snorm16, .y v2.xy as snorm10 (bits 0-9, 10-19) and beta as unorm12 (bits 20-31). v1, v2 have
// max-norm 1, so each keeps its largest component exactly; v2 is within 1/1022, beta within 1/8190.
// common/advection_step.glsl unpacks it.
uvec2 packVectors(vec4 v, float beta) {
  uvec2 v2 = uvec2(ivec2(round(clamp(v.zw, -1.0, 1.0) * 511.0))) & 0x3FFu;
  uint b = uint(round(clamp(beta, 0.0, 1.0) * 4095.0));
  return uvec2(packSnorm2x16(v.xy), v2.x | (v2.y << 10) | (b << 20));
}

// What the tensor stage writes for one pixel (see fabric/projection.frag's outputs).
struct Projection {
  uvec2 vectors;
  vec4 surface;
  vec4 eigen;
  vec4 lambda; // .w: 1 where the data's cover ramp applies (ALONG: times the proximity weight), multiplied by
               // the ramp by the caller
  // .xyz: per population packUnorm4x8(|d_k|, weight_k); .w packUnorm4x8(FA, the data's cover, the background
  // grey, 0), written by the caller once the cover ramp is applied (fibreAttributes)
  uvec4 fibres;
  uvec4 vectors3; // fibre sets: .xy `vectors`, .z population 3's direction (packSnorm2x16), .w 0
};

// The tensor stage at pixel px, whose ray meets the near and far clip planes at nearEye and farEye (eye
// space). `edge`: the data's edge field here; the cover ramp needs its screen-space width, which the
// caller takes (fwidth in a fragment shader, the 2x2 quads of a compute shader's work group).
Projection projectPixel(ivec2 px, vec3 nearEye, vec3 farEye, out float edge) {
  uvec2 g = imageLoad(u_geometry, px).xy;
  float depth = uintBitsToFloat(g.y);
  // The eye position on the pixel's ray at linear depth `depth` (eye z = -depth).
  vec3 eye = mix(nearEye, farEye, (-depth - nearEye.z) / (farEye.z - nearEye.z));
  vec3 world = (u_eyeToWorld * vec4(eye, 1.0)).xyz;
  vec3 n = fromOctahedral(unpackSnorm2x16(g.x));
  if (any(isnan(n))) n = vec3(0.0, 0.0, 1.0);
  vec3 nEye = normalize(u_viewRot * n);
  vec3 toEye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-eye);
  if (dot(nEye, toEye) < 0.0) { // two-sided: back faces (e.g. a slice seen from below) face the camera
    nEye = -nEye;
  }
  float light = blinnPhong(nEye, toEye, vec3(u_ambient, u_diffuse, u_specular));
  vec3 an = abs(n);
  float lod = noiseLod(depth, abs(dot(nEye, toEye)), max(an.x, max(an.y, an.z)));
  float beta = sampleNoise(world, n, lod);

  vec4 vectors = vec4(0.0);
  vec4 eigen = vec4(0.0);
#ifdef UNCERTAINTY
  // Tensors: .r; fibre sets: slot k's cone in component k.
  vec3 coneRad = radians(90.0) * u_fray *
                 texture(u_uncertainty, (u_uncertaintyWorldToTex * vec4(world, 1.0)).xyz).rgb;
#endif
  vec4 lambda = vec4(0.0);
  float fa;
#ifdef FIBRES
  vec3 fdir[3];
  float famp[3];
  vec2 v3 = vec2(0.0);
  uvec4 fibres = uvec4(0u);
  // Decoded a little beyond the data's edge; the edge is the blurred occupancy's 0.5 contour, a coverage ramp
  // one pixel wide as for tensors.
  int count = sampleFibres(world, 0.02, fdir, famp, fa, edge);
  if (count > 0 && fa >= u_faFloor) {
    vec4 c0 = u_viewProj * vec4(world, 1.0);
    int strongest = famp[1] > famp[0] ? (famp[2] > famp[1] ? 2 : 1) : (famp[2] > famp[0] ? 2 : 0);
    float top = famp[strongest];
    vec2 img[3];
    for (int k = 0; k < 3; ++k) {
      img[k] = vec2(0.0);
      if (famp[k] <= 0.0) continue;
      vec3 pd = fdir[k] - n * dot(n, fdir[k]); // P d
      float inPlane = length(pd);
#ifdef UNCERTAINTY
      pd = frayRotate(pd, n, coneRad[k] * frayDraw(world, u_noiseOrigin, u_lod, u_frayCells, uint(k)));
#endif
      if (inPlane > 0.05) img[k] = imageDirection(c0, pd / inPlane);
      float weight = clamp(famp[k] / top, 0.0, 1.0) * inPlane;
      fibres[k] = packUnorm4x8(vec4(abs(fdir[k]), weight));
    }
    vectors = vec4(img[0], img[1]);
    v3 = img[2];
    eigen.xyz = abs(fdir[strongest]);
    lambda.y = abs(dot(fdir[strongest], n));
    lambda.x = (famp[0] + famp[1] + famp[2] - top) / (2.0 * top);
    lambda.w = 1.0;
  }
#else
  mat3 t;
  float valid;
  // Tensors are decoded a little beyond the data's edge (the advection runs on across it); the edge itself is
  // the 0.5 contour of the blurred mask sampled trilinearly, drawn as a coverage ramp one pixel wide (its
  // change per pixel from the screen-space derivative): a smooth sub-voxel outline, never the voxel lattice.
  bool decoded = sampleTensorValid(world, 0.02, t, fa, valid);
  edge = dataEdge(world);
  if (decoded && fa >= u_faFloor) {
    // Eq. 1-2: T' = P T P^T with P = I - n n^T. T' has n as an eigenvector with eigenvalue 0, so the
    // closed-form solver's "separated eigenvector + 2x2 sub-problem" step reduces to the 2x2 problem in
    // the tangent plane, where u^T T' w = u^T T w for u, w orthogonal to n: T' need not be formed.
    vec3 e1p, e2p;
    float l1, l2; // eigenvalues of T' in the plane, l1 >= l2
    eigenPlaneValues(t, n, e1p, e2p, l1, l2);
    float mag = max(abs(l1), abs(l2));
    bool directional = mag > 0.0 && (l1 - l2) > u_degenerateTol * mag;
    if (directional) {
      vec4 c0 = u_viewProj * vec4(world, 1.0);
#ifdef UNCERTAINTY
      float turn = coneRad.x * frayDraw(world, u_noiseOrigin, u_lod, u_frayCells, 0u);
      e1p = frayRotate(e1p, n, turn);
      e2p = frayRotate(e2p, n, turn);
#endif
      vectors = vec4(imageDirection(c0, e1p), imageDirection(c0, e2p));
    }
#ifdef WITH_PRINCIPAL
    vec3 e1 = principalEigenvector(t);
    eigen.xyz = abs(e1);
    lambda.y = abs(dot(e1, n));
#endif
    lambda.x = l1 > 0.0 ? clamp(l2 / l1, 0.0, 1.0) : 1.0;
    lambda.w = 1.0;
  }
#endif
#ifdef BACKGROUND
  // The grey beneath the fabric (everywhere: the anatomy look shows it through isotropic tissue).
  lambda.z = texture(u_background, (u_backgroundWorldToTex * vec4(world, 1.0)).xyz).r;
#endif
#ifdef ALONG
  // The fabric only near the streamlines: their proximity weight scales the fabric's cover, so away from
  // them the composite shows what it shows where there is no tensor data (the background volume). The
  // directions stay, so the threads run on unbroken where the weight returns.
  lambda.w *= texture(u_along, world * u_alongScale + u_alongOffset).r;
#endif
  Projection r;
  r.vectors = packVectors(vectors, beta);
#ifdef FIBRES
  r.fibres = fibres;
  r.vectors3 = uvec4(r.vectors, packSnorm2x16(v3), 0u);
#else
  r.fibres = uvec4(0u);
  r.vectors3 = uvec4(0u);
#endif
  r.surface = vec4(beta, light, depth, 1.0);
  eigen.w = fa;
  r.eigen = eigen;
  r.lambda = lambda;
  return r;
}

// The fibres texel's .w: what the composite of a fibre set needs of eigen and lambda (as their 8-bit targets
// hold them), in the texel it reads anyway.
uint fibreAttributes(Projection p) { return packUnorm4x8(vec4(p.eigen.w, p.lambda.w, p.lambda.z, 0.0)); }

// The data's cover ramp, one pixel wide: 0..1 across the edge field's 0.5 contour, whose change per pixel is
// edgeWidth (|d/dx| + |d/dy|).
float coverRamp(float edge, float edgeWidth) {
  return clamp((edge - 0.5) / max(edgeWidth, 1e-4) + 0.5, 0.0, 1.0);
}
