// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dtf {

glm::dvec3 Grid::toVoxel(const glm::dvec3& xyz) const {
  return glm::dvec3(glm::inverse(voxelToWorld) * glm::dvec4(xyz, 1.0));
}

glm::dmat3 Grid::rotation() const {
  glm::dmat3 m(voxelToWorld);
  for (int c = 0; c < 3; ++c) {
    double n = glm::length(m[c]);
    if (n > 0) m[c] /= n;
  }
  // Polar decomposition by Newton iteration: converges to the nearest orthogonal matrix (keeps reflections).
  if (std::abs(glm::determinant(m)) < 1e-12) return glm::dmat3(1.0);
  for (int it = 0; it < 30; ++it) {
    glm::dmat3 next = 0.5 * (m + glm::transpose(glm::inverse(m)));
    double diff = 0;
    for (int c = 0; c < 3; ++c)
      diff += glm::length(next[c] - m[c]);
    m = next;
    if (diff < 1e-14) break;
  }
  return m;
}

std::string Grid::orientationCode() const {
  glm::dmat3 r = rotation();
  std::string code;
  static const char pos[3] = {'R', 'A', 'S'};
  static const char neg[3] = {'L', 'P', 'I'};
  for (int c = 0; c < 3; ++c) {
    int best = 0;
    for (int a = 1; a < 3; ++a)
      if (std::abs(r[c][a]) > std::abs(r[c][best])) best = a;
    code += r[c][best] >= 0 ? pos[best] : neg[best];
  }
  return code;
}

bool Grid::sameAs(const Grid& other, double toleranceMm) const {
  if (dims != other.dims) return false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(voxelToWorld[c][r] - other.voxelToWorld[c][r]) > toleranceMm) return false;
  return true;
}

void Grid::worldBounds(glm::dvec3& lo, glm::dvec3& hi) const {
  lo = glm::dvec3(std::numeric_limits<double>::max());
  hi = glm::dvec3(std::numeric_limits<double>::lowest());
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 ijk((c & 1) ? dims.x - 1 : 0, (c & 2) ? dims.y - 1 : 0, (c & 4) ? dims.z - 1 : 0);
    glm::dvec3 w = toWorld(ijk);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
}

Grid Grid::fromAffine(const glm::ivec3& d, const glm::dmat4& a) {
  Grid g;
  g.dims = d;
  g.voxelToWorld = a;
  for (int c = 0; c < 3; ++c)
    g.spacing[c] = glm::length(glm::dvec3(a[c]));
  return g;
}

} // namespace dtf
