// SPDX-License-Identifier: GPL-3.0-or-later
// Closed-form eigen-decomposition of a symmetric 3x3 matrix: the GLSL port of eigenDecompose in
// io/model/tensor.cpp (the CPU reference). Eigenvalues from the trigonometric solution of the
// characteristic polynomial; the best-separated eigenvector as the largest cross product of two rows of
// (A - lambda I); the other two from the 2x2 problem in the plane orthogonal to it. Repeated eigenvalues,
// zero and diagonal matrices give a finite orthonormal basis, never NaN.

const float kEigenPi = 3.14159265358979;

vec3 eigenAnyOrthogonal(vec3 v) {
  vec3 a = abs(v.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  return normalize(cross(v, a));
}

bool eigenNullVector(mat3 a, float lambda, out vec3 v) {
  // Rows of A - lambda I (A is symmetric, so rows equal columns).
  vec3 r0 = vec3(a[0][0] - lambda, a[1][0], a[2][0]);
  vec3 r1 = vec3(a[0][1], a[1][1] - lambda, a[2][1]);
  vec3 r2 = vec3(a[0][2], a[1][2], a[2][2] - lambda);
  vec3 c0 = cross(r0, r1), c1 = cross(r0, r2), c2 = cross(r1, r2);
  float n0 = dot(c0, c0), n1 = dot(c1, c1), n2 = dot(c2, c2);
  vec3 best = c0;
  float nb = n0;
  if (n1 > nb) { best = c1; nb = n1; }
  if (n2 > nb) { best = c2; nb = n2; }
  if (!(nb > 1e-30)) { v = vec3(1.0, 0.0, 0.0); return false; }
  v = best * inversesqrt(nb);
  return true;
}

// Eigenvectors of A restricted to the plane orthogonal to `axis`: (larger, smaller).
void eigenPlane(mat3 a, vec3 axis, out vec3 big, out vec3 small) {
  vec3 u = eigenAnyOrthogonal(axis);
  vec3 w = cross(axis, u);
  float m00 = dot(u, a * u), m01 = dot(u, a * w), m11 = dot(w, a * w);
  float y = 2.0 * m01, x = m00 - m11;
  float theta = abs(x) + abs(y) > 0.0 ? 0.5 * atan(y, x) : 0.0; // atan(0, 0) is undefined in GLSL
  big = cos(theta) * u + sin(theta) * w;
  small = cross(axis, big);
}

// values: descending; vectors[i]: unit eigenvector of values[i] (right-handed set).
void eigenDecompose(mat3 a, out vec3 values, out mat3 vectors) {
  values = vec3(0.0);
  vectors = mat3(1.0);
  float xx = a[0][0], yy = a[1][1], zz = a[2][2];
  float xy = a[1][0], xz = a[2][0], yz = a[2][1];
  float scale = max(max(max(abs(xx), abs(yy)), max(abs(zz), abs(xy))), max(abs(xz), abs(yz)));
  if (!(scale > 0.0) || isinf(scale) || isnan(scale)) return;
  // Work on A / scale: keeps float precision for tensors in mm^2/s (~1e-3) and curvatures alike.
  mat3 b = a / scale;
  xx /= scale; yy /= scale; zz /= scale; xy /= scale; xz /= scale; yz /= scale;
  float p1 = xy * xy + xz * xz + yz * yz;
  float q = (xx + yy + zz) / 3.0;
  float p2 = (xx - q) * (xx - q) + (yy - q) * (yy - q) + (zz - q) * (zz - q) + 2.0 * p1;
  float p = sqrt(p2 / 6.0);
  if (p <= 1e-6) { // isotropic: any basis
    values = vec3(q * scale);
    return;
  }
  mat3 bb = (b - q * mat3(1.0)) / p;
  float r = clamp(determinant(bb) * 0.5, -1.0, 1.0);
  float phi = acos(r) / 3.0;
  float l1 = q + 2.0 * p * cos(phi);
  float l3 = q + 2.0 * p * cos(phi + 2.0 * kEigenPi / 3.0);
  float l2 = clamp(3.0 * q - l1 - l3, l3, l1);
  vec3 v1, v2, v3;
  if (l1 - l2 >= l2 - l3) {
    eigenNullVector(b, l1, v1);
    eigenPlane(b, v1, v2, v3);
  } else {
    if (!eigenNullVector(b, l3, v3)) v3 = vec3(0.0, 0.0, 1.0);
    eigenPlane(b, v3, v1, v2);
  }
  v3 = cross(v1, v2);
  values = vec3(l1, l2, l3) * scale;
  vectors = mat3(v1, v2, v3);
}

// The 2x2 sub-problem alone, without trigonometry: eigenvectors of A restricted to the plane orthogonal to
// the unit vector `axis` (larger first) and their eigenvalues. The eigenvector of the larger eigenvalue of
// [[a, b], [b, c]] is (b, l1 - a) or (l1 - c, b), whichever is longer (the other may vanish). Returns
// equal eigenvalues and an arbitrary basis when the plane problem is isotropic.
void eigenPlaneValues(mat3 m, vec3 axis, out vec3 big, out vec3 small, out float l1, out float l2) {
  vec3 u = eigenAnyOrthogonal(axis);
  vec3 w = cross(axis, u);
  vec3 mu = m * u, mw = m * w;
  float a = dot(u, mu), b = dot(u, mw), c = dot(w, mw);
  float h = 0.5 * (a - c);
  float r = sqrt(h * h + b * b);
  float mean = 0.5 * (a + c);
  l1 = mean + r;
  l2 = mean - r;
  vec2 e0 = vec2(b, l1 - a), e1 = vec2(l1 - c, b);
  float n0 = dot(e0, e0), n1 = dot(e1, e1);
  vec2 e = n0 >= n1 ? e0 : e1;
  float n = max(n0, n1);
  e = n > 0.0 ? e * inversesqrt(n) : vec2(1.0, 0.0);
  big = e.x * u + e.y * w;
  small = cross(axis, big);
}

// The unit eigenvector of the largest eigenvalue of symmetric A (any unit vector when A is isotropic), for
// the DEC colour: eigenDecompose's first vector by the same branches, with one null vector (that of the
// better separated of l1 and l3) and without its trigonometric 2x2 step (a software rasteriser executes
// every branch, so each must be cheap). cos(phi + 2 pi / 3) = -cos(phi) / 2 - sin(phi) sqrt(3) / 2 with
// sin(phi) >= 0 for phi in [0, pi / 3]: one cosine and a square root instead of two cosines.
vec3 principalEigenvector(mat3 a) {
  float xx = a[0][0], yy = a[1][1], zz = a[2][2];
  float xy = a[1][0], xz = a[2][0], yz = a[2][1];
  float scale = max(max(max(abs(xx), abs(yy)), max(abs(zz), abs(xy))), max(abs(xz), abs(yz)));
  if (!(scale > 0.0) || isinf(scale) || isnan(scale)) return vec3(1.0, 0.0, 0.0);
  mat3 b = a / scale;
  xx /= scale; yy /= scale; zz /= scale; xy /= scale; xz /= scale; yz /= scale;
  float q = (xx + yy + zz) / 3.0;
  float p2 = (xx - q) * (xx - q) + (yy - q) * (yy - q) + (zz - q) * (zz - q) + 2.0 * (xy * xy + xz * xz + yz * yz);
  float p = sqrt(p2 / 6.0);
  if (p <= 1e-6) return vec3(1.0, 0.0, 0.0);
  float r = clamp(determinant((b - q * mat3(1.0)) / p) * 0.5, -1.0, 1.0);
  float c = cos(acos(r) / 3.0);
  float l1 = q + 2.0 * p * c;
  float l3 = q + p * (-c - sqrt(3.0 * max(1.0 - c * c, 0.0)));
  float l2 = clamp(3.0 * q - l1 - l3, l3, l1);
  bool first = l1 - l2 >= l2 - l3;
  vec3 v;
  bool found = eigenNullVector(b, first ? l1 : l3, v);
  if (first) return v;
  if (!found) v = vec3(0.0, 0.0, 1.0);
  vec3 big, small;
  float m1, m2;
  eigenPlaneValues(b, v, big, small, m1, m2);
  return big;
}
