// SPDX-License-Identifier: GPL-3.0-or-later
// Regions of interest for ROI selection of streamlines (`dtfabric select`, targeted `track`, the viewer's
// regions): spheres, axis-aligned boxes and masks in world RAS mm, each an include, exclude or ordered include
// region, and the rules a streamline must meet. The semantics are MRtrix 3.0.3 tckedit's on the stored
// vertices: a vertex is in a sphere when its distance to the centre is at most the radius (in single
// precision, as tckedit), in a box when every coordinate lies within the box's range, and in a mask when the
// voxel it rounds to (nearest index) is non-zero. Includes are ANDed, excludes ORed; ordered includes must be
// entered in their given order along the stored vertex order. `precise` also tests the segments between
// vertices exactly (spheres and boxes analytically, masks by walking the voxels a segment crosses).
// Parsing specs and files (images, labels, the JSON region set) is in ui/session/region_spec.h.
#pragma once

#include "io/model/volume.h"

#include <glm/glm.hpp>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace dtf::surfaces {

enum class RegionKind { Include, Exclude, IncludeOrdered };
enum class RegionShape { Sphere, Box, Mask };

// "include", "exclude", "include-ordered"; "sphere", "box", "mask".
const char* kindName(RegionKind k);
const char* shapeName(RegionShape s);

struct Region {
  RegionKind kind = RegionKind::Include;
  RegionShape shape = RegionShape::Sphere;
  std::string name;         // shown in lists and reports; the spec text when none is given
  glm::dvec3 centre{0.0};   // Sphere, world RAS mm
  double radius = 0.0;      // Sphere, mm
  glm::dvec3 lo{0.0}, hi{0.0}; // Box corners, world RAS mm, lo <= hi
  std::shared_ptr<const MaskVolume> mask; // Mask: non-zero voxels are inside (labels already resolved)
  std::string image;        // Mask: the image file it came from ("" when built in memory)
  std::vector<int> labels;  // Mask: the labels of `image` it holds (empty: every non-zero voxel)

  // A point's membership, with tckedit's rules (single precision for spheres, nearest voxel for masks).
  bool contains(const glm::vec3& p) const;
  // A world point that stands for the region: the sphere's or box's centre, the mean of a mask's voxels.
  glm::dvec3 centreOf() const;
  // World axis-aligned bounds of everything inside (a mask: its non-zero voxels' cells).
  void bounds(glm::dvec3& lo, glm::dvec3& hi) const;
};

// Throws InputError naming the region when it is not a usable region: a radius that is not finite and
// positive, non-finite coordinates, an inverted or empty box, a mask without voxels inside, or a mask whose
// affine is singular.
void validate(const Region& r);

// A region set with its rules: what `select` applies and the viewer edits.
struct RegionSet {
  std::vector<Region> regions; // ordered includes are entered in the order they stand here
  bool endsOnly = false;       // test includes and excludes on the two end points only
  bool precise = false;        // also test the segments between vertices
  double minLengthMm = 0.0;    // keep streamlines whose arc length lies in [min, max]
  double maxLengthMm = std::numeric_limits<double>::infinity();

  bool hasLengthRange() const { return minLengthMm > 0.0 || maxLengthMm < std::numeric_limits<double>::infinity(); }
  bool hasRegions() const { return !regions.empty(); }
};

// Throws InputError for a bad region (validate) or length range (negative, NaN, min > max).
void validate(const RegionSet& set);

} // namespace dtf::surfaces
