// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/slices.h"

#include "io/model/error.h"

#include <cmath>

namespace dtf::surfaces {

SliceAxis parseSliceAxis(const std::string& name) {
  if (name == "axial") return SliceAxis::Axial;
  if (name == "coronal") return SliceAxis::Coronal;
  if (name == "sagittal") return SliceAxis::Sagittal;
  throw UsageError("unknown slice axis '" + name + "' (axial, coronal, sagittal)");
}

const char* sliceAxisName(SliceAxis a) {
  switch (a) {
  case SliceAxis::Axial: return "axial";
  case SliceAxis::Coronal: return "coronal";
  case SliceAxis::Sagittal: return "sagittal";
  }
  return "?";
}

namespace {
int worldAxis(SliceAxis a) { return a == SliceAxis::Sagittal ? 0 : a == SliceAxis::Coronal ? 1 : 2; }

bool cellKept(const SliceOptions& o, const glm::ivec3 corners[4]) {
  if (!o.clip) return true;
  int passing = 0;
  for (int c = 0; c < 4; ++c)
    if (o.clip->at(corners[c].x, corners[c].y, corners[c].z) >= o.clipFloor) ++passing;
  return o.anyCorner ? passing > 0 : passing == 4;
}

// Drops vertices no triangle uses and renumbers the indices.
void compact(Mesh& m) {
  std::vector<std::int64_t> remap(m.positions.size(), -1);
  std::vector<glm::vec3> pos, nrm;
  for (auto& i : m.indices) {
    if (remap[i] < 0) {
      remap[i] = static_cast<std::int64_t>(pos.size());
      pos.push_back(m.positions[i]);
      nrm.push_back(m.normals[i]);
    }
    i = static_cast<std::uint32_t>(remap[i]);
  }
  m.positions = std::move(pos);
  m.normals = std::move(nrm);
}
} // namespace

int voxelAxisFor(const Grid& grid, SliceAxis axis) {
  glm::dmat3 r = grid.rotation();
  int w = worldAxis(axis), best = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(r[c][w]) > std::abs(r[best][w])) best = c;
  return best;
}

int sliceCount(const Grid& grid, SliceAxis axis) { return grid.dims[voxelAxisFor(grid, axis)]; }

Mesh makeSlice(const Grid& grid, SliceAxis axis, int index, const SliceOptions& options) {
  const int a = voxelAxisFor(grid, axis);
  if (index < 0 || index >= grid.dims[a])
    throw InputError(std::string(sliceAxisName(axis)) + " slice " + std::to_string(index) + " is outside the volume (0.." +
                     std::to_string(grid.dims[a] - 1) + ")");
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  const int nu = grid.dims[u], nv = grid.dims[v];
  glm::dvec3 normal(0.0);
  normal[worldAxis(axis)] = 1.0;
  // The plane's true normal is the affine's a-th row of the inverse; for oblique acquisitions it differs
  // slightly from the world axis.
  glm::dmat3 inv = glm::inverse(glm::dmat3(grid.voxelToWorld));
  glm::dvec3 n(inv[0][a], inv[1][a], inv[2][a]);
  n = glm::normalize(n);
  if (glm::dot(n, normal) < 0) n = -n;

  Mesh m;
  m.positions.reserve(static_cast<std::size_t>(nu) * nv);
  for (int jv = 0; jv < nv; ++jv)
    for (int iu = 0; iu < nu; ++iu) {
      glm::dvec3 ijk(0.0);
      ijk[a] = index;
      ijk[u] = iu;
      ijk[v] = jv;
      m.positions.push_back(glm::vec3(grid.toWorld(ijk)));
    }
  m.normals.assign(m.positions.size(), glm::vec3(n));
  // Winding: counter-clockwise seen from the side the normal points to.
  glm::dvec3 du = grid.toWorld(glm::dvec3(u == 0, u == 1, u == 2)) - grid.toWorld(glm::dvec3(0.0));
  glm::dvec3 dv = grid.toWorld(glm::dvec3(v == 0, v == 1, v == 2)) - grid.toWorld(glm::dvec3(0.0));
  const bool ccw = glm::dot(glm::cross(du, dv), n) > 0;
  for (int jv = 0; jv + 1 < nv; ++jv)
    for (int iu = 0; iu + 1 < nu; ++iu) {
      glm::ivec3 corners[4];
      for (int c = 0; c < 4; ++c) {
        corners[c][a] = index;
        corners[c][u] = iu + (c & 1);
        corners[c][v] = jv + (c >> 1);
      }
      if (!cellKept(options, corners)) continue;
      std::uint32_t i00 = static_cast<std::uint32_t>(jv * nu + iu), i10 = i00 + 1,
                    i01 = static_cast<std::uint32_t>((jv + 1) * nu + iu), i11 = i01 + 1;
      if (ccw) m.indices.insert(m.indices.end(), {i00, i10, i11, i00, i11, i01});
      else m.indices.insert(m.indices.end(), {i00, i11, i10, i00, i01, i11});
    }
  compact(m);
  return m;
}

Mesh makePlane(const Grid& grid, const glm::dvec3& point, const glm::dvec3& normalIn, double stepMm,
               const SliceOptions& options) {
  if (!(stepMm > 0)) throw UsageError("plane sampling step must be positive");
  if (glm::length(normalIn) == 0) throw UsageError("plane normal must be non-zero");
  const glm::dvec3 n = glm::normalize(normalIn);
  glm::dvec3 t1 = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  glm::dvec3 t2 = glm::cross(n, t1);
  glm::dvec3 lo, hi;
  grid.worldBounds(lo, hi);
  const double half = glm::length(hi - lo) * 0.5 + stepMm;
  // Sample around the grid centre's projection onto the plane, so the whole grid is covered.
  const glm::dvec3 gc = 0.5 * (lo + hi);
  const glm::dvec3 centre = gc - glm::dot(gc - point, n) * n;
  const int steps = static_cast<int>(std::ceil(2 * half / stepMm)) + 1;
  if (static_cast<long long>(steps) * steps > 64LL * 1024 * 1024) throw UsageError("plane sampling step too fine");
  Mesh m;
  std::vector<std::int64_t> vid(static_cast<std::size_t>(steps) * steps, -1);
  std::vector<glm::dvec3> vox(static_cast<std::size_t>(steps) * steps);
  auto inside = [&](const glm::dvec3& p) {
    return p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x <= grid.dims.x - 1 && p.y <= grid.dims.y - 1 &&
           p.z <= grid.dims.z - 1;
  };
  for (int b = 0; b < steps; ++b)
    for (int c = 0; c < steps; ++c) {
      glm::dvec3 w = centre + (-half + c * stepMm) * t1 + (-half + b * stepMm) * t2;
      vox[static_cast<std::size_t>(b) * steps + c] = grid.toVoxel(w);
    }
  auto keep = [&](const glm::dvec3& p) {
    if (!inside(p)) return false;
    if (!options.clip) return true;
    return sampleTrilinear(*options.clip, p) >= options.clipFloor;
  };
  auto keepCell = [&](std::size_t k) {
    if (!options.anyCorner)
      return keep(vox[k]) && keep(vox[k + 1]) && keep(vox[k + steps]) && keep(vox[k + steps + 1]);
    for (std::size_t q : {k, k + 1, k + steps, k + steps + 1})
      if (!inside(vox[q])) return false;
    return keep(vox[k]) || keep(vox[k + 1]) || keep(vox[k + steps]) || keep(vox[k + steps + 1]);
  };
  auto vertex = [&](int b, int c) {
    std::size_t k = static_cast<std::size_t>(b) * steps + c;
    if (vid[k] < 0) {
      vid[k] = static_cast<std::int64_t>(m.positions.size());
      m.positions.push_back(glm::vec3(grid.toWorld(vox[k])));
      m.normals.push_back(glm::vec3(n));
    }
    return static_cast<std::uint32_t>(vid[k]);
  };
  for (int b = 0; b + 1 < steps; ++b)
    for (int c = 0; c + 1 < steps; ++c) {
      const std::size_t k = static_cast<std::size_t>(b) * steps + c;
      if (!keepCell(k)) continue;
      std::uint32_t i00 = vertex(b, c), i10 = vertex(b, c + 1), i01 = vertex(b + 1, c), i11 = vertex(b + 1, c + 1);
      // t1 x t2 = n, so (c, b) order is counter-clockwise seen from +n.
      m.indices.insert(m.indices.end(), {i00, i10, i11, i00, i11, i01});
    }
  return m;
}

} // namespace dtf::surfaces
