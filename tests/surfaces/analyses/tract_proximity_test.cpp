// SPDX-License-Identifier: GPL-3.0-or-later
// The proximity weight the fabric is drawn through (--fabric-along): against the exact distance of each
// voxel centre to a polyline, within the stated bounds; the grid's extent and voxel size; bad distances.
#include "io/model/error.h"
#include "surfaces/analyses/tract_proximity.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

using dtf::Polylines;
namespace sf = dtf::surfaces;

namespace {

double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
  return glm::length(p - glm::mix(a, b, t));
}

} // namespace

TEST(TractProximity, TheWeightFollowsTheExactDistanceWithinTheStatedBounds) {
  // A bent line with uneven, oblique segments (2.7 mm apart at most) and a second short one; a third line is
  // left out by `lines`.
  Polylines t;
  t.offsets = {0};
  const std::vector<glm::vec3> a = {{-10.3f, 2.1f, 0.4f}, {-7.9f, 2.9f, 1.3f}, {-5.2f, 3.2f, 2.0f},
                                    {-3.0f, 5.0f, 2.5f},  {-1.1f, 6.9f, 3.8f}, {0.2f, 9.3f, 4.1f}};
  const std::vector<glm::vec3> b = {{5.0f, -4.0f, -3.0f}, {5.5f, -2.0f, -3.4f}};
  const std::vector<glm::vec3> c = {{30.0f, 30.0f, 30.0f}, {31.0f, 30.0f, 30.0f}};
  for (const auto* line : {&a, &b, &c}) {
    t.points.insert(t.points.end(), line->begin(), line->end());
    t.offsets.push_back(static_cast<std::uint32_t>(t.points.size()));
  }
  const std::vector<std::uint32_t> used = {0, 1};
  sf::TractProximityOptions o;
  o.mm = 3.0;
  const sf::TractProximity near = sf::tractProximity(t, o, &used);
  EXPECT_EQ(near.points, a.size() + b.size());
  EXPECT_DOUBLE_EQ(near.voxelMm, 0.75);
  const dtf::Grid& g = near.weight.grid;
  // The box of the used points grown by mm + 2 h: the third line's far point is outside.
  glm::dvec3 lo, hi;
  g.worldBounds(lo, hi);
  EXPECT_NEAR(lo.x, -10.3 - 4.5, 1e-4);
  EXPECT_GE(hi.y, 9.3 + 4.5 - 1e-4);
  EXPECT_LT(hi.x, 20.0);
  const double h = near.voxelMm;
  int inside = 0, outside = 0, ramp = 0;
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        const glm::dvec3 p = g.toWorld({i, j, k});
        double d = 1e9;
        for (std::size_t s = 0; s + 1 < a.size(); ++s)
          d = std::min(d, segmentDistance(p, a[s], a[s + 1]));
        d = std::min(d, segmentDistance(p, b[0], b[1]));
        const float w = near.weight.at(i, j, k);
        ASSERT_GE(w, 0.0f);
        ASSERT_LE(w, 1.0f);
        if (d <= o.mm - 1.7 * h) {
          ++inside;
          ASSERT_EQ(w, 1.0f) << "at distance " << d;
        } else if (d >= o.mm + 2.2 * h) {
          ++outside;
          ASSERT_EQ(w, 0.0f) << "at distance " << d;
        } else {
          ++ramp;
        }
      }
  EXPECT_GT(inside, 300);
  EXPECT_GT(outside, 10000);
  EXPECT_GT(ramp, 0);
}

TEST(TractProximity, ACoarserGridKeepsTheVoxelCountWithinItsLimit) {
  Polylines t;
  t.offsets = {0};
  t.points = {{-70.0f, -90.0f, -60.0f}, {70.0f, 90.0f, 70.0f}};
  t.offsets.push_back(2);
  sf::TractProximityOptions o;
  o.mm = 2.0;
  o.maxVoxels = 1u << 20;
  const sf::TractProximity near = sf::tractProximity(t, o);
  EXPECT_LE(near.weight.grid.voxelCount(), o.maxVoxels);
  EXPECT_GT(near.voxelMm, 1.0);
  // The segment's midpoint is stamped at any grid size.
  const glm::dvec3 m = glm::round(near.weight.grid.toVoxel({0.0, 0.0, 5.0}));
  EXPECT_EQ(near.weight.at(int(m.x), int(m.y), int(m.z)), 1.0f);
}

TEST(TractProximity, NoPointGivesAnEmptyVolumeAndBadDistancesAreRefused) {
  Polylines t;
  t.offsets = {0, 0};
  EXPECT_EQ(sf::tractProximity(t, {}).weight.grid.voxelCount(), 0u);
  for (double mm : {0.0, -1.0, std::nan(""), 1e9}) {
    sf::TractProximityOptions o;
    o.mm = mm;
    EXPECT_THROW(sf::tractProximity(t, o), dtf::InputError) << mm;
  }
}
