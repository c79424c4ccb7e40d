#version 450 core
// Projection pass (paper §2.1 and §2.3, Eq. 1-5 and 7-9). Per fragment: interpolate the tensor, project it
// onto the tangent plane (T' = P T P^T, P = I - n n^T), decompose T', take its two in-plane eigenvectors,
// project each to image space as the pixel difference of p + eps v and p (perspective-correct), and scale
// by the max-norm. Also writes the mapped noise beta, light intensity, depth, normal, FA, the in-plane
// eigenvalues and the 3D principal eigenvector. A cleared (zero) vector means "no direction here".
#include "common/eigen.glsl"
#include "common/tensor_field.glsl"
#include "common/lighting.glsl"

in vec3 v_world;
in vec3 v_normal;
in vec3 v_eye;

uniform mat4 u_viewProj;
uniform mat3 u_viewRot;      // world -> eye rotation (normals)
uniform vec2 u_targetSize;   // guarded target size in pixels
uniform float u_eps;         // mm; finite-difference step along the eigenvectors
uniform float u_degenerateTol = 0.02; // relative in-plane eigenvalue gap below which there is no direction
uniform bool u_orthographic;
uniform vec3 u_noiseOrigin;  // b_min of Eq. 7 (world mm)
uniform float u_lod;         // l of Eq. 7: implicit voxel edge in mm
uniform float u_noiseBlend = 0.0; // 0 = Eq. 9 exactly; > 0 softens the switch between voxel faces
layout(binding = 2) uniform sampler2D u_noise;

layout(location = 0) out vec4 o_vectors; // v1.xy, v2.xy: image-space directions (pixels, max-norm 1)
layout(location = 1) out vec4 o_surface; // beta, light L, linear depth (mm from the eye), 1 = covered
layout(location = 2) out vec4 o_normal;  // eye-space unit normal (facing the camera), FA
layout(location = 3) out vec4 o_eigen;   // world principal eigenvector of T (unit), lambda2'/lambda1'
layout(location = 4) out vec4 o_lambda;  // lambda1', lambda2' (mm^2/s), |e1 . n|, 1 = tensor data here

// Image-space direction of world direction v at p: the pixel difference of the projections of p + eps v
// and p (perspective-correct; the clip position of p + eps v is c0 + eps M (v, 0) by linearity), max-norm
// scaled (Eq. 4-5); zero when it degenerates (v along the view ray).
vec2 imageDirection(vec4 c0, vec3 v) {
  vec4 c1 = c0 + u_eps * (u_viewProj * vec4(v, 0.0));
  vec2 d = (c1.xy / c1.w - c0.xy / c0.w) * 0.5 * u_targetSize;
  float m = max(abs(d.x), abs(d.y));
  return m > 1e-4 ? d / m : vec2(0.0);
}

float sampleNoise(vec3 p, vec3 n) {
  vec3 vox = (p - u_noiseOrigin) / u_lod; // Eq. 7
  vec3 an = abs(n);
  // Gradients of the continuous voxel coordinate: the mip level without the seams of fract().
  vec3 dx = dFdx(vox), dy = dFdy(vox);
  if (u_noiseBlend > 0.0) { // softened switch between voxel faces (not Eq. 9 exactly)
    float bx = textureGrad(u_noise, fract(vox.yz), dx.yz, dy.yz).r;
    float by = textureGrad(u_noise, fract(vox.xz), dx.xz, dy.xz).r;
    float bz = textureGrad(u_noise, fract(vox.xy), dx.xy, dy.xy).r;
    vec3 w = pow(an, vec3(1.0 / u_noiseBlend));
    return dot(w, vec3(bx, by, bz)) / max(w.x + w.y + w.z, 1e-6);
  }
  // Eq. 8-9: the two components of frac(vox) spanning the voxel face whose normal is closest to n.
  vec2 t, gx, gy;
  if (an.x >= an.y && an.x >= an.z) {
    t = vox.yz; gx = dx.yz; gy = dy.yz;
  } else if (an.y >= an.z) {
    t = vox.xz; gx = dx.xz; gy = dy.xz;
  } else {
    t = vox.xy; gx = dx.xy; gy = dy.xy;
  }
  // textureLod with the level from the continuous coordinates: the same mip choice as textureGrad
  // (isotropic), far cheaper on software rasterisers.
  vec2 size = vec2(textureSize(u_noise, 0));
  float rho = max(dot(gx * size, gx * size), dot(gy * size, gy * size));
  return textureLod(u_noise, fract(t), max(0.5 * log2(max(rho, 1e-12)), 0.0)).r;
}

void main() {
  vec3 n = normalize(v_normal);
  if (any(isnan(n))) n = vec3(0.0, 0.0, 1.0);
  vec3 nEye = normalize(u_viewRot * n);
  vec3 toEye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v_eye);
  if (dot(nEye, toEye) < 0.0) { // two-sided: back faces (e.g. a slice seen from below) face the camera
    nEye = -nEye;
  }
  float light = blinnPhong(nEye, toEye);
  float beta = sampleNoise(v_world, n);
  float depth = -v_eye.z;

  vec4 vectors = vec4(0.0);
  vec4 eigen = vec4(0.0, 0.0, 0.0, 1.0);
  vec4 lambda = vec4(0.0);
  mat3 t;
  float fa;
  if (sampleTensor(v_world, t, fa)) {
    mat3 P = mat3(1.0) - outerProduct(n, n);   // Eq. 2
    mat3 tp = P * t * transpose(P);            // Eq. 1
    // T' has n as an eigenvector with eigenvalue 0 by construction, so the closed-form solver's
    // "separated eigenvector + 2x2 sub-problem" step reduces to the 2x2 problem in the tangent plane.
    vec3 e1p, e2p;
    eigenPlane(tp, n, e1p, e2p);
    float l1 = dot(e1p, tp * e1p), l2 = dot(e2p, tp * e2p); // l1 >= l2
    float mag = max(abs(l1), abs(l2));
    bool directional = mag > 0.0 && (l1 - l2) > u_degenerateTol * mag;
    if (directional) {
      vec4 c0 = u_viewProj * vec4(v_world, 1.0);
      vectors = vec4(imageDirection(c0, e1p), imageDirection(c0, e2p));
    }
#ifdef WITH_PRINCIPAL
    vec3 tv;
    mat3 tvecs;
    eigenDecompose(t, tv, tvecs);
    vec3 e1 = tvecs[0];
    eigen.xyz = e1;
    lambda.z = abs(dot(e1, n));
#endif
    eigen.w = directional && l1 > 0.0 ? clamp(l2 / l1, 0.0, 1.0) : 1.0;
    lambda.xy = vec2(l1, l2);
    lambda.w = 1.0;
  }
  o_vectors = vectors;
  o_surface = vec4(beta, light, depth, 1.0);
  o_normal = vec4(nEye, fa);
  o_eigen = eigen;
  o_lambda = lambda;
}
