// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/tensor.h"

#include <algorithm>
#include <cmath>

namespace dtf {

SymTensor SymTensor::fromMat(const glm::dmat3& m) {
  // glm is column-major: m[col][row]; symmetrise to absorb rounding.
  SymTensor t;
  t.xx = static_cast<float>(m[0][0]);
  t.yy = static_cast<float>(m[1][1]);
  t.zz = static_cast<float>(m[2][2]);
  t.xy = static_cast<float>(0.5 * (m[1][0] + m[0][1]));
  t.xz = static_cast<float>(0.5 * (m[2][0] + m[0][2]));
  t.yz = static_cast<float>(0.5 * (m[2][1] + m[1][2]));
  return t;
}

glm::dmat3 SymTensor::toMat() const {
  return glm::dmat3(xx, xy, xz, xy, yy, yz, xz, yz, zz);
}

bool SymTensor::isFinite() const {
  for (float v : components())
    if (!std::isfinite(v)) return false;
  return true;
}

namespace {

glm::dvec3 anyOrthogonal(const glm::dvec3& v) {
  glm::dvec3 a = std::abs(v.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(v, a));
}

// Unit eigenvector of an eigenvalue that is separated from the other two: the largest cross product of
// two rows of (A - lambda I) spans its null space.
bool nullVector(const glm::dmat3& a, double lambda, glm::dvec3& out) {
  glm::dvec3 r0(a[0][0] - lambda, a[1][0], a[2][0]);
  glm::dvec3 r1(a[0][1], a[1][1] - lambda, a[2][1]);
  glm::dvec3 r2(a[0][2], a[1][2], a[2][2] - lambda);
  glm::dvec3 c[3] = {glm::cross(r0, r1), glm::cross(r0, r2), glm::cross(r1, r2)};
  double n[3] = {glm::dot(c[0], c[0]), glm::dot(c[1], c[1]), glm::dot(c[2], c[2])};
  int best = 0;
  if (n[1] > n[best]) best = 1;
  if (n[2] > n[best]) best = 2;
  if (!(n[best] > 0) || !std::isfinite(n[best])) return false;
  out = c[best] / std::sqrt(n[best]);
  return true;
}

// Eigenvectors of A restricted to the plane orthogonal to `axis`; returns (larger, smaller).
void planeEigen(const glm::dmat3& a, const glm::dvec3& axis, glm::dvec3& big, glm::dvec3& small) {
  glm::dvec3 u = anyOrthogonal(axis);
  glm::dvec3 w = glm::cross(axis, u);
  double m00 = glm::dot(u, a * u), m01 = glm::dot(u, a * w), m11 = glm::dot(w, a * w);
  double theta = 0.5 * std::atan2(2.0 * m01, m00 - m11); // angle of the larger eigenvector in (u, w)
  big = std::cos(theta) * u + std::sin(theta) * w;
  small = glm::cross(axis, big);
}

} // namespace

EigenSystem eigenDecompose(const glm::dmat3& a) {
  EigenSystem e;
  double xx = a[0][0], yy = a[1][1], zz = a[2][2];
  double xy = a[1][0], xz = a[2][0], yz = a[2][1];
  if (!std::isfinite(xx + yy + zz + xy + xz + yz)) return e; // zeros, identity basis
  double scale = std::max({std::abs(xx), std::abs(yy), std::abs(zz), std::abs(xy), std::abs(xz), std::abs(yz)});
  if (scale == 0) return e;
  double p1 = xy * xy + xz * xz + yz * yz;
  double q = (xx + yy + zz) / 3.0;
  double p2 = (xx - q) * (xx - q) + (yy - q) * (yy - q) + (zz - q) * (zz - q) + 2.0 * p1;
  double p = std::sqrt(p2 / 6.0);
  if (p <= 1e-12 * scale) { // isotropic: any basis
    e.values = glm::dvec3(q);
    return e;
  }
  glm::dmat3 b = (1.0 / p) * (a - q * glm::dmat3(1.0));
  double r = std::clamp(glm::determinant(b) / 2.0, -1.0, 1.0);
  double phi = std::acos(r) / 3.0;
  double l1 = q + 2.0 * p * std::cos(phi);
  double l3 = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  double l2 = std::clamp(3.0 * q - l1 - l3, l3, l1);
  e.values = glm::dvec3(l1, l2, l3);

  // Solve for the eigenvector whose eigenvalue is best separated, then the 2x2 problem orthogonal to it.
  glm::dvec3 v1, v2, v3;
  if (l1 - l2 >= l2 - l3) {
    if (!nullVector(a, l1, v1)) v1 = glm::dvec3(1, 0, 0);
    planeEigen(a, v1, v2, v3);
  } else {
    if (!nullVector(a, l3, v3)) v3 = glm::dvec3(0, 0, 1);
    planeEigen(a, v3, v1, v2);
  }
  // Right-handed set: v3 = v1 x v2.
  v3 = glm::cross(v1, v2);
  e.vectors = {v1, v2, v3};
  return e;
}

double fractionalAnisotropy(const glm::dvec3& l) {
  double den = l.x * l.x + l.y * l.y + l.z * l.z;
  if (!(den > 0)) return 0;
  double num = (l.x - l.y) * (l.x - l.y) + (l.y - l.z) * (l.y - l.z) + (l.z - l.x) * (l.z - l.x);
  return std::clamp(std::sqrt(0.5 * num / den), 0.0, 1.0);
}

double fractionalAnisotropy(const SymTensor& t) {
  const double q = (static_cast<double>(t.xx) + t.yy + t.zz) / 3.0;
  const double off = 2.0 * (static_cast<double>(t.xy) * t.xy + static_cast<double>(t.xz) * t.xz +
                            static_cast<double>(t.yz) * t.yz);
  const double dxx = t.xx - q, dyy = t.yy - q, dzz = t.zz - q;
  const double norm2 = static_cast<double>(t.xx) * t.xx + static_cast<double>(t.yy) * t.yy +
                       static_cast<double>(t.zz) * t.zz + off;
  if (!(norm2 > 0)) return 0;
  const double dev2 = dxx * dxx + dyy * dyy + dzz * dzz + off;
  return std::clamp(std::sqrt(1.5 * dev2 / norm2), 0.0, 1.0);
}

double tensorMode(const glm::dmat3& d) {
  double q = (d[0][0] + d[1][1] + d[2][2]) / 3.0;
  glm::dmat3 dev = d - q * glm::dmat3(1.0);
  double norm2 = 0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) norm2 += dev[c][r] * dev[c][r];
  if (!(norm2 > 1e-30)) return 0;
  double m = 3.0 * std::sqrt(6.0) * glm::determinant(dev / std::sqrt(norm2));
  return std::clamp(m, -1.0, 1.0);
}

TensorMetrics computeMetrics(const EigenSystem& e) {
  TensorMetrics m;
  const glm::dvec3& l = e.values;
  m.fa = fractionalAnisotropy(l);
  m.md = (l.x + l.y + l.z) / 3.0;
  m.ad = l.x;
  m.rd = 0.5 * (l.y + l.z);
  glm::dmat3 d(0.0);
  for (int i = 0; i < 3; ++i) d += l[i] * glm::outerProduct(e.vectors[i], e.vectors[i]);
  m.mode = tensorMode(d);
  return m;
}

glm::dvec3 decColor(const EigenSystem& e, double fa) {
  double f = std::clamp(fa, 0.0, 1.0);
  return glm::abs(e.vectors[0]) * f;
}

SymTensor rotateTensor(const SymTensor& t, const glm::dmat3& r) {
  return SymTensor::fromMat(r * t.toMat() * glm::transpose(r));
}

} // namespace dtf
