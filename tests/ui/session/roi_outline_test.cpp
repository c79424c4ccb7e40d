// SPDX-License-Identifier: GPL-3.0-or-later
// Region outlines on a slice plane (ui/session/roi_outline.h): a mask's outline against the rectangle its
// voxels' cells cut from an axial plane (closed form), and the planes and regions that give none.
#include "ui/session/roi_outline.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <memory>

using namespace dtf;

namespace {

// A 20^3 grid of 1 mm voxels at world (x - 3, y + 2, z - 1), with voxels i 5..14, j 6..12, k 3..16 set: their
// cells fill world x in [1.5, 11.5], y in [7.5, 14.5], z in [1.5, 15.5].
surfaces::Region boxMask() {
  Grid g = Grid::fromAffine({20, 20, 20}, glm::translate(glm::dmat4(1.0), glm::dvec3(-3, 2, -1)));
  auto m = std::make_shared<MaskVolume>(g, 1);
  for (int k = 3; k <= 16; ++k)
    for (int j = 6; j <= 12; ++j)
      for (int i = 5; i <= 14; ++i)
        m->at(i, j, k) = 1;
  surfaces::Region r;
  r.shape = surfaces::RegionShape::Mask;
  r.mask = m;
  return r;
}

} // namespace

TEST(RegionOutline, AMaskIsOutlinedAlongItsVoxelsCellsOnTheSlice) {
  const surfaces::Region mask = boxMask();
  std::vector<glm::dvec3> seg;
  std::vector<unsigned char> scratch;
  const glm::dvec3 point(0, 0, 8.3), normal(0, 0, 1);
  ASSERT_TRUE(session::maskOutline(mask, point, normal, seg, scratch));
  ASSERT_EQ(seg.size() % 2, 0u);
  const double x0 = 1.5, x1 = 11.5, y0 = 7.5, y1 = 14.5, h = 0.5; // lattice spacing: half a voxel
  double length = 0;
  int sides[4] = {0, 0, 0, 0};
  for (std::size_t k = 0; k < seg.size(); k += 2) {
    length += glm::length(seg[k + 1] - seg[k]);
    for (const glm::dvec3& p : {seg[k], seg[k + 1]}) {
      EXPECT_NEAR(p.z, 8.3, 1e-9); // on the plane
      // Within half a lattice step of the rectangle's boundary (the samples straddle it).
      const double dx = std::min(std::abs(p.x - x0), std::abs(p.x - x1));
      const double dy = std::min(std::abs(p.y - y0), std::abs(p.y - y1));
      const bool inX = p.x > x0 - h && p.x < x1 + h, inY = p.y > y0 - h && p.y < y1 + h;
      EXPECT_TRUE((dx <= 0.5 * h + 1e-9 && inY) || (dy <= 0.5 * h + 1e-9 && inX)) << p.x << " " << p.y;
    }
    const glm::dvec3 m = 0.5 * (seg[k] + seg[k + 1]);
    sides[0] += std::abs(m.x - x0) < h, sides[1] += std::abs(m.x - x1) < h;
    sides[2] += std::abs(m.y - y0) < h, sides[3] += std::abs(m.y - y1) < h;
  }
  EXPECT_NEAR(length, 2 * ((x1 - x0) + (y1 - y0)), 4 * h); // the perimeter, to a lattice step per side
  for (int s : sides)
    EXPECT_GE(s, 10) << "every side of the rectangle is outlined";
  // A plane beside the mask, and shapes that are not masks, give no mask outline.
  EXPECT_FALSE(session::maskOutline(mask, glm::dvec3(0, 0, 17), normal, seg, scratch));
  EXPECT_TRUE(seg.empty());
  surfaces::Region sphere;
  sphere.centre = glm::dvec3(5, 10, 8);
  sphere.radius = 3;
  EXPECT_FALSE(session::maskOutline(sphere, point, normal, seg, scratch));
  EXPECT_FALSE(session::regionOutline(mask, point, normal, seg));
  // An oblique plane through the mask still cuts it, and its outline stays on the plane.
  const glm::dvec3 oblique = glm::normalize(glm::dvec3(1, 1, 1)), through(6.5, 11, 8.5);
  ASSERT_TRUE(session::maskOutline(mask, through, oblique, seg, scratch));
  for (const glm::dvec3& p : seg)
    EXPECT_NEAR(glm::dot(p - through, oblique), 0.0, 1e-9);
}
