// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/selection/regions.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace dtf::surfaces {

const char* kindName(RegionKind k) {
  switch (k) {
  case RegionKind::Include:
    return "include";
  case RegionKind::Exclude:
    return "exclude";
  case RegionKind::IncludeOrdered:
    return "include-ordered";
  }
  return "?";
}

const char* shapeName(RegionShape s) {
  switch (s) {
  case RegionShape::Sphere:
    return "sphere";
  case RegionShape::Box:
    return "box";
  case RegionShape::Mask:
    return "mask";
  }
  return "?";
}

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Index bounds of a mask's non-zero voxels; false when it has none.
bool maskIndexBounds(const MaskVolume& m, glm::ivec3& lo, glm::ivec3& hi) {
  lo = glm::ivec3(std::numeric_limits<int>::max());
  hi = glm::ivec3(std::numeric_limits<int>::min());
  bool any = false;
  for (int k = 0; k < m.grid.dims.z; ++k)
    for (int j = 0; j < m.grid.dims.y; ++j)
      for (int i = 0; i < m.grid.dims.x; ++i)
        if (m.data[m.grid.index(i, j, k) * static_cast<std::size_t>(m.components)]) {
          lo = glm::min(lo, glm::ivec3(i, j, k));
          hi = glm::max(hi, glm::ivec3(i, j, k));
          any = true;
        }
  return any;
}

} // namespace

bool Region::contains(const glm::vec3& p) const {
  switch (shape) {
  case RegionShape::Sphere: {
    const glm::vec3 d = glm::vec3(centre) - p;
    const float r = static_cast<float>(radius);
    return glm::dot(d, d) <= r * r;
  }
  case RegionShape::Box:
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  case RegionShape::Mask: {
    const glm::dvec3 v = mask->grid.toVoxel(glm::dvec3(p));
    const int i = static_cast<int>(std::lround(v.x)), j = static_cast<int>(std::lround(v.y)),
              k = static_cast<int>(std::lround(v.z));
    if (!mask->grid.contains(i, j, k)) return false;
    return mask->data[mask->grid.index(i, j, k) * static_cast<std::size_t>(mask->components)] != 0;
  }
  }
  return false;
}

glm::dvec3 Region::centreOf() const {
  switch (shape) {
  case RegionShape::Sphere:
    return centre;
  case RegionShape::Box:
    return 0.5 * (lo + hi);
  case RegionShape::Mask: {
    glm::dvec3 sum(0.0);
    double n = 0;
    const Grid& g = mask->grid;
    for (int k = 0; k < g.dims.z; ++k)
      for (int j = 0; j < g.dims.y; ++j)
        for (int i = 0; i < g.dims.x; ++i)
          if (mask->data[g.index(i, j, k) * static_cast<std::size_t>(mask->components)]) {
            sum += glm::dvec3(i, j, k);
            n += 1;
          }
    return n > 0 ? g.toWorld(sum / n) : g.toWorld(glm::dvec3(g.dims) * 0.5);
  }
  }
  return centre;
}

void Region::bounds(glm::dvec3& outLo, glm::dvec3& outHi) const {
  switch (shape) {
  case RegionShape::Sphere:
    outLo = centre - glm::dvec3(radius);
    outHi = centre + glm::dvec3(radius);
    return;
  case RegionShape::Box:
    outLo = lo;
    outHi = hi;
    return;
  case RegionShape::Mask: {
    glm::ivec3 a, b;
    outLo = glm::dvec3(std::numeric_limits<double>::max());
    outHi = glm::dvec3(std::numeric_limits<double>::lowest());
    if (!maskIndexBounds(*mask, a, b)) return;
    // The cells' corners (a vertex rounds into voxel v within v +- 0.5).
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 ijk((c & 1) ? b.x + 0.5 : a.x - 0.5, (c & 2) ? b.y + 0.5 : a.y - 0.5,
                           (c & 4) ? b.z + 0.5 : a.z - 0.5);
      const glm::dvec3 w = mask->grid.toWorld(ijk);
      outLo = glm::min(outLo, w);
      outHi = glm::max(outHi, w);
    }
    return;
  }
  }
}

void validate(const Region& r) {
  const std::string what = std::string(kindName(r.kind)) + " region '" + r.name + "'";
  switch (r.shape) {
  case RegionShape::Sphere:
    if (!finite(r.centre)) throw InputError(what + ": the centre is not finite");
    if (!std::isfinite(r.radius) || r.radius <= 0)
      throw InputError(what + ": the radius must be a positive number of mm");
    return;
  case RegionShape::Box:
    if (!finite(r.lo) || !finite(r.hi)) throw InputError(what + ": a corner is not finite");
    if (r.lo.x > r.hi.x || r.lo.y > r.hi.y || r.lo.z > r.hi.z)
      throw InputError(what + ": the box is inverted (each of X0,Y0,Z0 must be at most X1,Y1,Z1)");
    return;
  case RegionShape::Mask: {
    if (!r.mask) throw InputError(what + ": no mask");
    const double det = glm::determinant(glm::dmat3(r.mask->grid.voxelToWorld));
    if (!std::isfinite(det) || std::abs(det) < 1e-12)
      throw InputError(what + ": the image's voxel-to-world affine is singular");
    glm::ivec3 a, b;
    if (!maskIndexBounds(*r.mask, a, b)) throw InputError(what + ": the mask has no voxel inside");
    return;
  }
  }
}

void validate(const RegionSet& set) {
  for (const Region& r : set.regions)
    validate(r);
  if (std::isnan(set.minLengthMm) || std::isnan(set.maxLengthMm) || set.minLengthMm < 0 || set.maxLengthMm < 0)
    throw InputError("the length range must be numbers >= 0 mm");
  if (set.minLengthMm > set.maxLengthMm) {
    std::ostringstream s;
    s << "the minimum length " << set.minLengthMm << " mm exceeds the maximum " << set.maxLengthMm << " mm";
    throw InputError(s.str());
  }
}

} // namespace dtf::surfaces
