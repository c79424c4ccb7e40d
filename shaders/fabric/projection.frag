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

vec2 toPixel(vec3 p) {
  vec4 c = u_viewProj * vec4(p, 1.0);
  return (c.xy / c.w * 0.5 + 0.5) * u_targetSize;
}

// Image-space direction of world direction v at p, max-norm scaled; zero when it degenerates.
vec2 imageDirection(vec3 p, vec3 v) {
  vec2 d = toPixel(p + u_eps * v) - toPixel(p);
  float m = max(abs(d.x), abs(d.y));
  return m > 1e-4 ? d / m : vec2(0.0);
}

float sampleNoise(vec3 p, vec3 n) {
  vec3 vox = (p - u_noiseOrigin) / u_lod; // Eq. 7
  vec3 hit = fract(vox);                   // Eq. 8
  vec3 an = abs(n);
  // Gradients of the continuous voxel coordinate: mip level without the seams of fract().
  vec3 dx = dFdx(vox), dy = dFdy(vox);
  float bx = textureGrad(u_noise, hit.yz, dx.yz, dy.yz).r;
  float by = textureGrad(u_noise, hit.xz, dx.xz, dy.xz).r;
  float bz = textureGrad(u_noise, hit.xy, dx.xy, dy.xy).r;
  if (u_noiseBlend <= 0.0) { // Eq. 9: the voxel face whose normal is closest to the surface normal
    if (an.x >= an.y && an.x >= an.z) return bx;
    return an.y >= an.z ? by : bz;
  }
  vec3 w = pow(an, vec3(1.0 / u_noiseBlend));
  return dot(w, vec3(bx, by, bz)) / max(w.x + w.y + w.z, 1e-6);
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
    vec3 vals;
    mat3 vecs;
    eigenDecompose(tp, vals, vecs);
    // The eigenvector along n (eigenvalue 0) is not in the plane: drop the one most aligned with n.
    vec3 an = abs(vec3(dot(vecs[0], n), dot(vecs[1], n), dot(vecs[2], n)));
    int drop = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
    int ia = drop == 0 ? 1 : 0;
    int ib = drop == 2 ? 1 : 2;
    float l1 = vals[ia], l2 = vals[ib]; // descending
    vec3 e1p = vecs[ia], e2p = vecs[ib];
    float mag = max(abs(l1), abs(l2));
    bool directional = mag > 0.0 && (l1 - l2) > u_degenerateTol * mag;
    if (directional) vectors = vec4(imageDirection(v_world, e1p), imageDirection(v_world, e2p));
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
