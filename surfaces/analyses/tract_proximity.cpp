// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/analyses/tract_proximity.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dtf::surfaces {

namespace {

constexpr double kFar = 1e20; // "no seed" in the squared distance transform

// One line of the squared Euclidean distance transform (Felzenszwalb and Huttenlocher 2012): d[q] =
// min_p (q - p)^2 + f[p]. v, z: work arrays of n and n + 1 entries.
void distanceLine(const double* f, int n, double* d, int* v, double* z) {
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    const auto meet = [&](int p) {
      return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
    };
    double s = meet(v[k]);
    while (s <= z[k])
      s = meet(v[--k]); // z[0] = -inf: k stays >= 0
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q)
      ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

// The squared distance transform of `g` (kFar off the seeds, 0 on them) in place, in voxel units, along i,
// then j, then k.
void distanceTransform(std::vector<double>& g, const glm::ivec3& dims) {
  const int n = std::max({dims.x, dims.y, dims.z});
  std::vector<double> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  const std::size_t sx = 1, sy = std::size_t(dims.x), sz = std::size_t(dims.x) * dims.y;
  const auto pass = [&](int len, std::size_t stride, std::size_t count, auto start) {
    for (std::size_t line = 0; line < count; ++line) {
      const std::size_t s0 = start(line);
      for (int q = 0; q < len; ++q)
        f[q] = g[s0 + q * stride];
      distanceLine(f.data(), len, d.data(), v.data(), z.data());
      for (int q = 0; q < len; ++q)
        g[s0 + q * stride] = d[q];
    }
  };
  const std::size_t nx = dims.x, ny = dims.y, nz = dims.z;
  pass(dims.x, sx, ny * nz, [&](std::size_t l) { return l * sy; });
  pass(dims.y, sy, nx * nz, [&](std::size_t l) { return (l / nx) * sz + l % nx; });
  pass(dims.z, sz, nx * ny, [&](std::size_t l) { return l; });
}

} // namespace

TractProximity tractProximity(const Polylines& tracts, const TractProximityOptions& options,
                              const std::vector<std::uint32_t>* lines) {
  const double mm = options.mm;
  if (!(std::isfinite(mm) && mm > 0.0 && mm <= 1000.0))
    throw InputError("the distance along the tracts must be a number of mm in (0, 1000], got " +
                     std::to_string(mm));
  TractProximity out;
  out.mm = mm;
  const std::size_t lineCount = lines ? lines->size() : tracts.lineCount();
  const auto lineAt = [&](std::size_t i) { return lines ? std::size_t((*lines)[i]) : i; };
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::size_t i = 0; i < lineCount; ++i) {
    const std::size_t l = lineAt(i);
    if (l >= tracts.lineCount())
      throw InputError("streamline " + std::to_string(l) + " is not in the tracts");
    for (std::uint32_t p = tracts.offsets[l]; p < tracts.offsets[l + 1]; ++p) {
      const glm::dvec3 x(tracts.points[p]);
      if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) continue;
      lo = glm::min(lo, x);
      hi = glm::max(hi, x);
      ++out.points;
    }
  }
  if (out.points == 0) return out;

  double h = std::clamp(mm / 4.0, 0.5, 1.0);
  glm::ivec3 dims;
  glm::dvec3 origin;
  for (;;) {
    const double margin = mm + 2.0 * h;
    origin = lo - margin;
    dims = glm::ivec3(glm::ceil((hi - lo + 2.0 * margin) / h)) + 1;
    if (std::size_t(dims.x) * dims.y * dims.z <= options.maxVoxels) break;
    h *= 1.1;
  }
  out.voxelMm = h;
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = h;
  a[3] = glm::dvec4(origin, 1.0);
  const Grid grid = Grid::fromAffine(dims, a);

  std::vector<double> g(grid.voxelCount(), kFar);
  const auto seed = [&](const glm::dvec3& x) {
    const glm::ivec3 v(glm::round((x - origin) / h));
    if (grid.contains(v.x, v.y, v.z)) g[grid.index(v.x, v.y, v.z)] = 0.0;
  };
  for (std::size_t i = 0; i < lineCount; ++i) {
    const std::size_t l = lineAt(i);
    const std::uint32_t b = tracts.offsets[l], e = tracts.offsets[l + 1];
    for (std::uint32_t p = b; p < e; ++p) {
      const glm::dvec3 x(tracts.points[p]);
      if (!std::isfinite(x.x + x.y + x.z)) continue;
      seed(x);
      if (p + 1 >= e) continue;
      const glm::dvec3 y(tracts.points[p + 1]);
      if (!std::isfinite(y.x + y.y + y.z)) continue;
      const int steps = int(std::ceil(glm::length(y - x) / (0.5 * h)));
      for (int s = 1; s < steps; ++s)
        seed(glm::mix(x, y, double(s) / steps));
    }
  }
  distanceTransform(g, dims);
  out.weight = ScalarVolume(grid, 1);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double d = std::sqrt(g[i]) * h;
    out.weight.data[i] = float(std::clamp((mm - d) / h + 0.5, 0.0, 1.0));
  }
  return out;
}

} // namespace dtf::surfaces
