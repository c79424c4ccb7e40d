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

// A mask in 3D: the surface of its voxels' cells. The box mask (10 x 7 x 14 voxels) has 2 (10*7 + 10*14 +
// 7*14) faces on its cells' box [1.5, 11.5] x [7.5, 14.5] x [1.5, 15.5], and its creases are the box's 12
// edges cut into voxel-long pieces (4 (10 + 7 + 14) of them); one voxel added on a face makes 4 more faces,
// and its 12 edges are creases too. Past the face cap, only the bounds.
TEST(RegionOutline, AMaskIn3dIsItsVoxelsSurfaceWithTheCreasesAlongItsEdges) {
  surfaces::Region mask = boxMask();
  session::MaskSurface s;
  ASSERT_TRUE(session::maskSurface(mask, s));
  ASSERT_TRUE(s.drawn);
  EXPECT_EQ(s.faces.size(), 4u * 2 * (10 * 7 + 10 * 14 + 7 * 14));
  const glm::dvec3 lo(1.5, 7.5, 1.5), hi(11.5, 14.5, 15.5);
  EXPECT_NEAR(glm::length(s.lo - lo), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(s.hi - hi), 0.0, 1e-9);
  auto onBox = [&](const glm::dvec3& p) {
    int faces = 0;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p[a], lo[a] - 1e-9);
      EXPECT_LE(p[a], hi[a] + 1e-9);
      faces += std::abs(p[a] - lo[a]) < 1e-9 || std::abs(p[a] - hi[a]) < 1e-9;
    }
    return faces;
  };
  for (std::size_t f = 0; f < s.faces.size(); f += 4) {
    glm::dvec3 c(0.0);
    for (int t = 0; t < 4; ++t)
      c += 0.25 * s.faces[f + t];
    EXPECT_EQ(onBox(c), 1) << "a face's centre lies on one side of the box";
    EXPECT_NEAR(glm::length(s.faces[f + 2] - s.faces[f]), std::sqrt(2.0), 1e-9) << "a unit square";
  }
  ASSERT_EQ(s.creases.size(), 2u * 4 * (10 + 7 + 14));
  for (std::size_t e = 0; e < s.creases.size(); e += 2) {
    EXPECT_NEAR(glm::length(s.creases[e + 1] - s.creases[e]), 1.0, 1e-9);
    EXPECT_EQ(onBox(0.5 * (s.creases[e] + s.creases[e + 1])), 2) << "on an edge of the box";
  }
  // One voxel on top of the box (i 9, j 9, k 17): its top and four sides are new, the face beneath it is gone.
  auto bumped = std::make_shared<MaskVolume>(*mask.mask);
  bumped->at(9, 9, 17) = 1;
  mask.mask = bumped;
  ASSERT_TRUE(session::maskSurface(mask, s));
  EXPECT_EQ(s.faces.size(), 4u * (2 * (10 * 7 + 10 * 14 + 7 * 14) + 4));
  EXPECT_EQ(s.creases.size(), 2u * (4 * (10 + 7 + 14) + 12));
  // Past the cap: the bounds only.
  ASSERT_TRUE(session::maskSurface(mask, s, 100));
  EXPECT_FALSE(s.drawn);
  EXPECT_TRUE(s.faces.empty() && s.creases.empty());
  EXPECT_NEAR(s.hi.z, 16.5, 1e-9);
  // Not a mask, or an empty one: nothing.
  surfaces::Region sphere;
  sphere.radius = 3;
  EXPECT_FALSE(session::maskSurface(sphere, s));
  mask.mask = std::make_shared<MaskVolume>(mask.mask->grid, 1);
  EXPECT_FALSE(session::maskSurface(mask, s));
}
