// SPDX-License-Identifier: GPL-3.0-or-later
// The one tract-overlay rule of ui/session/tract_overlay.h that the viewer's worker uses (and `render
// --tracts` applies through the same pickTracts/tractClip): which tracts a surface shows, and what is
// uploaded of them (the display decimation to render::kTractDisplayPointCap with its levels of detail).
#include "render/reference/scenes.h"
#include "support/polylines.h"
#include "ui/session/tract_overlay.h"

#include <atomic>
#include <gtest/gtest.h>

using namespace dtf;
using namespace dtf::session;

namespace {

// Lines along x at heights y = 0..n-1 mm, crossing the plane x = 0 and a sphere of radius 10 at the origin.
Polylines crossingLines(std::size_t n) {
  Polylines l;
  l.offsets = {0};
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = -30; k <= 30; ++k)
      l.points.emplace_back(float(k), float(i), 0.0f);
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  return l;
}

} // namespace

TEST(TractOverlayRule, APlanarSurfaceShowsEveryTractInASlabAroundItsPlane) {
  const Mesh plane = render::reference::planeMesh({0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 40, 40, 4);
  const Polylines lines = crossingLines(5);
  const TractSelection s = selectTracts(lines, plane, 3.0);
  EXPECT_TRUE(s.all);
  ASSERT_TRUE(s.pick.plane.has_value());
  EXPECT_NEAR(std::abs((*s.pick.plane).x), 1.0f, 1e-5f); // the plane x = 0
  EXPECT_TRUE(s.near.points.empty());
  // Its slab: the near distance unless a clip half-width is given.
  TractOverlayOptions o;
  o.nearMm = 3.0;
  EXPECT_FLOAT_EQ(tractClip(s.pick, o, {0, 0, -1}, {0, 0, 0}).slabMm, 3.0f);
  o.clipMm = 1.5;
  EXPECT_FLOAT_EQ(tractClip(s.pick, o, {0, 0, -1}, {0, 0, 0}).slabMm, 1.5f);
}

TEST(TractOverlayRule, ACurvedSurfaceShowsThePiecesNearItOrEverythingAtDistanceZero) {
  const Mesh sphere = render::reference::uvSphere({0, 0, 0}, 10.0, 24, 48);
  const Polylines lines = crossingLines(5); // heights 0..4 mm: each line pierces the sphere twice
  const TractSelection near = selectTracts(lines, sphere, 1.0);
  EXPECT_FALSE(near.all);
  EXPECT_FALSE(near.pick.plane.has_value());
  ASSERT_GT(near.near.points.size(), 0u);
  EXPECT_LT(near.near.points.size(), lines.points.size());
  for (const glm::vec3& p : near.near.points)
    EXPECT_LT(std::abs(glm::length(p) - 10.0f), 1.0f + 0.1f) << p.x << " " << p.y;
  EXPECT_EQ(near.near.lineCount(), 10u); // two pieces per line
  const TractSelection all = selectTracts(lines, sphere, 0.0);
  EXPECT_TRUE(all.all);
  EXPECT_FALSE(all.pick.plane.has_value());
}

TEST(TractOverlayRule, PastThePointCapAnEvenSampleOfTheStreamlinesIsMeasured) {
  const Mesh sphere = render::reference::uvSphere({0, 0, 0}, 10.0, 24, 48);
  const Polylines lines = crossingLines(5);
  const TractSelection full = selectTracts(lines, sphere, 1.0);
  // A cap of half the points: every 2nd streamline (0, 2, 4), whole, gives exactly their pieces.
  const TractSelection half = selectTracts(lines, sphere, 1.0, nullptr, (lines.points.size() + 1) / 2);
  EXPECT_EQ(full.lineStep, 1u);
  ASSERT_EQ(half.lineStep, 2u);
  const TractSelection sampled = selectTracts(lines.subset({0, 2, 4}), sphere, 1.0);
  EXPECT_EQ(half.near.lineCount(), 6u); // two pieces per line
  EXPECT_EQ(half.near.offsets, sampled.near.offsets);
  EXPECT_TRUE(half.near.points == sampled.near.points);
  EXPECT_LT(half.near.points.size(), full.near.points.size());
}

TEST(TractOverlayRule, ACancelledSelectionStopsWithNothing) {
  const Mesh sphere = render::reference::uvSphere({0, 0, 0}, 10.0, 24, 48);
  const std::atomic<bool> cancel{true};
  const TractSelection s = selectTracts(crossingLines(50), sphere, 2.0, &cancel);
  EXPECT_FALSE(s.all);
  EXPECT_TRUE(s.near.points.empty());
}

TEST(TractOverlayRule, TheDisplayIsDecimatedToTheCapWithLevelsOfDetail) {
  // 2000 lines of 1000 points: twice the cap, so every other point is kept (first and last always).
  const Polylines big = test::gridLines(2000, 1000);
  const render::DisplayTracts d = tractOverlayDisplay(big);
  EXPECT_LE(d.points.size(), render::kTractDisplayPointCap);
  EXPECT_GT(d.points.size(), render::kTractDisplayPointCap / 2);
  EXPECT_EQ(d.lines, 2000u);
  EXPECT_GT(d.levelCount(), 1);
  // Small sets are uploaded whole.
  const Polylines small = test::gridLines(10, 50);
  const render::DisplayTracts s = tractOverlayDisplay(small);
  EXPECT_EQ(s.points.size(), small.points.size());
  EXPECT_EQ(s.segmentCount(0), 10u * 49u);
}
