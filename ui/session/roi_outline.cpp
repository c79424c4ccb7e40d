// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/roi_outline.h"

#include <algorithm>
#include <cmath>

namespace dtf::session {

glm::u8vec3 regionKindColour(surfaces::RegionKind kind) {
  switch (kind) {
  case surfaces::RegionKind::Include:
    return {60, 220, 80};
  case surfaces::RegionKind::Exclude:
    return {235, 50, 50};
  case surfaces::RegionKind::IncludeOrdered:
    return {70, 140, 255};
  }
  return {255, 255, 255};
}

const char* regionKindColourName(surfaces::RegionKind kind) {
  switch (kind) {
  case surfaces::RegionKind::Include:
    return "green";
  case surfaces::RegionKind::Exclude:
    return "red";
  case surfaces::RegionKind::IncludeOrdered:
    return "blue";
  }
  return "white";
}

namespace {
// Two unit vectors spanning the plane of unit normal n.
void planeAxes(const glm::dvec3& n, glm::dvec3& u, glm::dvec3& v) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  u = glm::normalize(glm::cross(n, a));
  v = glm::cross(n, u);
}
} // namespace

bool regionOutline(const surfaces::Region& r, const glm::dvec3& point, const glm::dvec3& normal,
                   std::vector<glm::dvec3>& out, int segments) {
  out.clear();
  const glm::dvec3 n = glm::normalize(normal);
  glm::dvec3 u, v;
  planeAxes(n, u, v);
  if (r.shape == surfaces::RegionShape::Sphere) {
    const double d = glm::dot(r.centre - point, n);
    if (std::abs(d) >= r.radius) return false;
    const double rho = std::sqrt(r.radius * r.radius - d * d);
    const glm::dvec3 c = r.centre - d * n;
    for (int k = 0; k < segments; ++k) {
      const double t = 2.0 * M_PI * k / segments;
      out.push_back(c + rho * (std::cos(t) * u + std::sin(t) * v));
    }
    return true;
  }
  if (r.shape != surfaces::RegionShape::Box) return false;
  // The plane against the box's 12 edges; the crossings ordered by angle around their mean.
  glm::dvec3 corner[8];
  for (int i = 0; i < 8; ++i)
    corner[i] = boxCorner(r, i);
  for (int i = 0; i < 8; ++i)
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (i & bit) continue;
      const glm::dvec3 a = corner[i], b = corner[i | bit];
      const double da = glm::dot(a - point, n), db = glm::dot(b - point, n);
      if ((da < 0) == (db < 0) || da == db) continue;
      out.push_back(a + (b - a) * (da / (da - db)));
    }
  if (out.size() < 3) {
    out.clear();
    return false;
  }
  glm::dvec3 mean(0.0);
  for (const auto& p : out)
    mean += p;
  mean /= static_cast<double>(out.size());
  std::sort(out.begin(), out.end(), [&](const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::dot(a - mean, v), glm::dot(a - mean, u)) <
           std::atan2(glm::dot(b - mean, v), glm::dot(b - mean, u));
  });
  return true;
}

} // namespace dtf::session
