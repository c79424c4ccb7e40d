// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/volume.h"

#include <cmath>

namespace dtf {

float sampleTrilinear(const ScalarVolume& v, const glm::dvec3& p, int c, float outside) {
  const glm::ivec3 d = v.grid.dims;
  if (p.x < 0 || p.y < 0 || p.z < 0 || p.x > d.x - 1 || p.y > d.y - 1 || p.z > d.z - 1) return outside;
  int i0 = static_cast<int>(std::floor(p.x)), j0 = static_cast<int>(std::floor(p.y)),
      k0 = static_cast<int>(std::floor(p.z));
  int i1 = std::min(i0 + 1, d.x - 1), j1 = std::min(j0 + 1, d.y - 1), k1 = std::min(k0 + 1, d.z - 1);
  double fx = p.x - i0, fy = p.y - j0, fz = p.z - k0;
  auto s = [&](int i, int j, int k) { return static_cast<double>(v.at(i, j, k, c)); };
  double c00 = s(i0, j0, k0) * (1 - fx) + s(i1, j0, k0) * fx;
  double c10 = s(i0, j1, k0) * (1 - fx) + s(i1, j1, k0) * fx;
  double c01 = s(i0, j0, k1) * (1 - fx) + s(i1, j0, k1) * fx;
  double c11 = s(i0, j1, k1) * (1 - fx) + s(i1, j1, k1) * fx;
  double c0 = c00 * (1 - fy) + c10 * fy, c1 = c01 * (1 - fy) + c11 * fy;
  return static_cast<float>(c0 * (1 - fz) + c1 * fz);
}

} // namespace dtf
