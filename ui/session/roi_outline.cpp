// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/roi_outline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

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

bool maskOutline(const surfaces::Region& r, const glm::dvec3& point, const glm::dvec3& normal,
                 std::vector<glm::dvec3>& out, std::vector<unsigned char>& scratch) {
  out.clear();
  if (r.shape != surfaces::RegionShape::Mask || !r.mask) return false;
  const glm::dvec3 n = glm::normalize(normal);
  glm::dvec3 u, v;
  planeAxes(n, u, v);
  glm::dvec3 lo, hi;
  r.bounds(lo, hi);
  double dMin = HUGE_VAL, dMax = -HUGE_VAL, u0 = HUGE_VAL, u1 = -HUGE_VAL, v0 = HUGE_VAL, v1 = -HUGE_VAL;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 c = glm::dvec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z) - point;
    const double d = glm::dot(c, n), a = glm::dot(c, u), b = glm::dot(c, v);
    dMin = std::min(dMin, d), dMax = std::max(dMax, d);
    u0 = std::min(u0, a), u1 = std::max(u1, a), v0 = std::min(v0, b), v1 = std::max(v1, b);
  }
  if (dMin > 0 || dMax < 0) return false; // the plane misses the mask's bounds
  const MaskVolume& m = *r.mask;
  const glm::dvec3 sp = m.grid.spacing;
  double h = 0.5 * std::min({sp.x, sp.y, sp.z});
  h = std::max(h, std::max(u1 - u0, v1 - v0) / (kMaskOutlineSamples - 3));
  if (!(h > 0) || !std::isfinite(h)) return false;
  // One sample of margin around the bounds: the outermost samples are outside.
  const int nu = static_cast<int>(std::ceil((u1 - u0) / h)) + 3, nv = static_cast<int>(std::ceil((v1 - v0) / h)) + 3;
  const glm::dvec3 origin = point + (u0 - h) * u + (v0 - h) * v;
  const glm::dmat4 toVoxel = glm::inverse(m.grid.voxelToWorld);
  const auto comps = static_cast<std::size_t>(m.components);
  scratch.assign(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv), 0);
  bool any = false;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      // The same rule as Region::contains: the point in single precision, the nearest voxel.
      const glm::vec3 p(origin + (i * h) * u + (j * h) * v);
      const glm::dvec3 x(toVoxel * glm::dvec4(glm::dvec3(p), 1.0));
      const int a = static_cast<int>(std::lround(x.x)), b = static_cast<int>(std::lround(x.y)),
                c = static_cast<int>(std::lround(x.z));
      if (!m.grid.contains(a, b, c) || m.data[m.grid.index(a, b, c) * comps] == 0) continue;
      scratch[static_cast<std::size_t>(j) * static_cast<std::size_t>(nu) + static_cast<std::size_t>(i)] = 1;
      any = true;
    }
  if (!any) return false;
  auto at = [&](int i, int j) {
    return scratch[static_cast<std::size_t>(j) * static_cast<std::size_t>(nu) + static_cast<std::size_t>(i)];
  };
  auto world = [&](double i, double j) { return origin + (i * h) * u + (j * h) * v; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i)
      if (at(i, j) != at(i + 1, j)) {
        out.push_back(world(i + 0.5, j - 0.5));
        out.push_back(world(i + 0.5, j + 0.5));
      }
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i < nu; ++i)
      if (at(i, j) != at(i, j + 1)) {
        out.push_back(world(i - 0.5, j + 0.5));
        out.push_back(world(i + 0.5, j + 0.5));
      }
  return true;
}

bool maskSurface(const surfaces::Region& r, MaskSurface& out, std::size_t maxFaces) {
  out = MaskSurface{};
  if (r.shape != surfaces::RegionShape::Mask || !r.mask) return false;
  const MaskVolume& m = *r.mask;
  const glm::ivec3 dims = m.grid.dims;
  const auto comps = static_cast<std::size_t>(m.components);
  auto inside = [&](int i, int j, int k) {
    return m.grid.contains(i, j, k) && m.data[m.grid.index(i, j, k) * comps] != 0;
  };
  // Faces in index space: the cell of voxel v spans v +- 0.5; face (v, axis, side) lies at v[axis] + side/2.
  struct Face {
    glm::ivec3 v;
    int axis, side;
  };
  std::vector<Face> faces;
  bool any = false, over = false;
  for (int k = 0; k < dims.z && !over; ++k)
    for (int j = 0; j < dims.y && !over; ++j)
      for (int i = 0; i < dims.x; ++i) {
        if (!inside(i, j, k)) continue;
        any = true;
        for (int axis = 0; axis < 3; ++axis)
          for (int side : {-1, 1}) {
            glm::ivec3 n(i, j, k);
            n[axis] += side;
            if (!inside(n.x, n.y, n.z)) faces.push_back({{i, j, k}, axis, side});
          }
        if (faces.size() > maxFaces) {
          over = true;
          break;
        }
      }
  if (!any) return false;
  r.bounds(out.lo, out.hi);
  if (over) return true;
  const glm::dmat4& toWorld = m.grid.voxelToWorld;
  auto world = [&](const glm::dvec3& x) { return glm::dvec3(toWorld * glm::dvec4(x, 1.0)); };
  // Each cell edge, as its lower corner (doubled index coordinates, so half-integers are whole) and axis,
  // with the orientations (axis * 2 + side) of the faces along it: an edge whose faces differ is a crease.
  std::unordered_map<std::uint64_t, std::array<int, 2>> edges; // up to two orientations seen (-1: none)
  auto edgeKey = [](const glm::ivec3& c2, int axis) {
    const auto f = [](int x) { return static_cast<std::uint64_t>(x + (1 << 19)) & 0xfffffu; };
    return (f(c2.x) << 42) | (f(c2.y) << 22) | (f(c2.z) << 2) | static_cast<std::uint64_t>(axis);
  };
  out.faces.reserve(faces.size() * 4);
  for (const Face& f : faces) {
    const int a = (f.axis + 1) % 3, b = (f.axis + 2) % 3;
    glm::dvec3 c(f.v);
    c[f.axis] += 0.5 * f.side;
    glm::dvec3 q[4];
    for (int t = 0; t < 4; ++t) {
      q[t] = c;
      q[t][a] += (t == 1 || t == 2) ? 0.5 : -0.5;
      q[t][b] += (t >= 2) ? 0.5 : -0.5;
      out.faces.push_back(world(q[t]));
    }
    const int orientation = f.axis * 2 + (f.side > 0);
    for (int t = 0; t < 4; ++t) {
      const glm::dvec3 p = q[t], s = q[(t + 1) % 4];
      const glm::dvec3 lo = glm::min(p, s);
      const int axis = p.x != s.x ? 0 : p.y != s.y ? 1 : 2;
      const glm::ivec3 c2(glm::round(2.0 * lo));
      auto [it, added] = edges.try_emplace(edgeKey(c2, axis), std::array<int, 2>{orientation, -1});
      if (!added && it->second[0] != orientation) it->second[1] = orientation;
      (void)it;
    }
  }
  for (const auto& [key, o] : edges) {
    if (o[1] < 0) continue;
    const auto g = [&](int shift) {
      return static_cast<double>(static_cast<int>((key >> shift) & 0xfffffu) - (1 << 19)) / 2.0;
    };
    const glm::dvec3 lo(g(42), g(22), g(2));
    glm::dvec3 hi = lo;
    hi[static_cast<int>(key & 3u)] += 1.0;
    out.creases.push_back(world(lo));
    out.creases.push_back(world(hi));
  }
  out.drawn = true;
  return true;
}

} // namespace dtf::session
