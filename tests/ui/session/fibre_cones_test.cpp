// SPDX-License-Identifier: GPL-3.0-or-later
// Per-population cones over a fibre set: each fibre takes the cone of the bedpostx population whose mean
// direction is nearest, whatever order the set holds its fibres in.
#include "ui/session/fibre_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace dtf;

TEST(FibreCones, EachFibreTakesTheConeOfTheNearestPopulation) {
  Grid grid;
  grid.dims = {2, 1, 1};
  auto samples = std::make_shared<io::BedpostxSamples>();
  samples->grid = grid;
  // Population 1 runs along y (cone 40), population 2 along x, slightly tilted (cone 5); in voxel 1
  // population 2 has no cone (too small a fraction).
  samples->cone = {ScalarVolume(grid, 1, 40.0f), ScalarVolume(grid, 1, 5.0f)};
  samples->cone[1].data[1] = std::nanf("");
  samples->mean = {Volume<float>(grid, 3), Volume<float>(grid, 3)};
  for (std::size_t v = 0; v < 2; ++v) {
    samples->mean[0].data[v * 3 + 1] = 1.0f;
    samples->mean[1].data[v * 3] = -0.995f; // the sign of a direction does not matter
    samples->mean[1].data[v * 3 + 2] = 0.0998f;
  }
  FibreSet set;
  set.grid = grid;
  set.maxFibres = 2;
  set.fibres = {{{1, 0, 0}, 0.6f}, {{0, 1, 0}, 0.3f}, {{1, 0, 0}, 0.5f}, {{0, 1, 0}, 0.4f}};
  session::UncertaintyMap map;
  map.cone = samples->cone[0];
  map.samples = samples;
  const ScalarVolume c = session::conesFor(map, &set);
  ASSERT_EQ(c.components, 2);
  EXPECT_EQ(c.data[0], 5.0f);  // x fibre: population 2
  EXPECT_EQ(c.data[1], 40.0f); // y fibre: population 1
  EXPECT_TRUE(std::isnan(c.data[2])); // x fibre, its population without a cone: none (not population 1's)
  EXPECT_EQ(c.data[3], 40.0f);
  // Without a fibre set, or on another grid: population 1's map.
  EXPECT_EQ(session::conesFor(map, nullptr).components, 1);
  FibreSet other = set;
  other.grid.dims = {1, 2, 1};
  EXPECT_EQ(session::conesFor(map, &other).components, 1);
}
