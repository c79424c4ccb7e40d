// SPDX-License-Identifier: GPL-3.0-or-later
// Levels of detail and the frame budget of the tract overlay (render/tract_renderer.h,
// render/tract_layer.h): CPU side, no GL.
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "support/polylines.h"

#include <cmath>
#include <gtest/gtest.h>
#include <map>
#include <set>

using namespace dtf;
using dtf::test::gridLines;

namespace {

// The lines (y of their points) that segments [a, b) of `level` belong to.
std::vector<int> linesOf(const render::DisplayTracts& d, int level, std::size_t a, std::size_t b) {
  std::vector<int> out;
  for (std::size_t s = d.levelOffsets[level] + a; s < d.levelOffsets[level] + b; ++s)
    out.push_back(static_cast<int>(d.points[d.segments[2 * s]].y));
  return out;
}

} // namespace

TEST(TractLevels, EachLevelHalvesTheSegmentsAndJoinsTheSameLinesEndToEnd) {
  const Polylines in = gridLines(64, 101); // 100 segments per line
  const render::DisplayTracts d = render::prepareDisplayTracts(in);
  EXPECT_EQ(d.points.size(), in.points.size());
  EXPECT_EQ(d.lines, 64u);
  ASSERT_EQ(d.levelCount(), 5);
  const std::size_t perLine[] = {100, 50, 25, 13, 7}; // steps 1, 2, 4, 8, 16
  for (int k = 0; k < d.levelCount(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(d.segmentCount(k), 64 * perLine[k]);
    // Per line, the level's segments form a chain from the first point to the last with steps 2^k (the
    // last one shorter).
    std::map<int, std::vector<std::pair<std::uint32_t, std::uint32_t>>> chains;
    for (std::size_t s = d.levelOffsets[k]; s < d.levelOffsets[k + 1]; ++s)
      chains[int(d.points[d.segments[2 * s]].y)].push_back({d.segments[2 * s], d.segments[2 * s + 1]});
    ASSERT_EQ(chains.size(), 64u);
    for (const auto& [line, chain] : chains) {
      EXPECT_EQ(chain.front().first, in.offsets[line]);
      EXPECT_EQ(chain.back().second, in.offsets[line + 1] - 1);
      for (std::size_t i = 0; i < chain.size(); ++i) {
        if (i) {
          EXPECT_EQ(chain[i].first, chain[i - 1].second);
        }
        EXPECT_LE(chain[i].second - chain[i].first, 1u << k);
      }
    }
  }
}

TEST(TractLevels, PrefixesSampleTheLinesEvenly) {
  const render::DisplayTracts d = render::prepareDisplayTracts(gridLines(1000, 3));
  // 2 segments per line at level 0; a prefix of 1/8 of the segments covers 125 lines spread over all 1000.
  const auto lines = linesOf(d, 0, 0, d.segmentCount(0) / 8);
  const std::set<int> distinct(lines.begin(), lines.end());
  EXPECT_EQ(distinct.size(), 125u);
  int buckets[10] = {};
  for (int l : distinct)
    ++buckets[l / 100];
  for (int b : buckets)
    EXPECT_NEAR(b, 12.5, 2.0);
}

TEST(TractLevels, ShortLinesGetNoUselessLevelsAndTheCapHolds) {
  EXPECT_EQ(render::prepareDisplayTracts(gridLines(100, 2)).levelCount(), 1);
  const render::DisplayTracts capped = render::prepareDisplayTracts(gridLines(100, 1000), 10'000);
  EXPECT_LE(capped.points.size(), 10'000u);
  EXPECT_EQ(capped.lines, 100u);
  EXPECT_TRUE(render::prepareDisplayTracts(Polylines{{}, {0}}).segments.empty());
}

TEST(TractBudget, LearnsACostPerLevelAndChoosesTheFinestLevelThatFits) {
  render::TractBudget b(20.0);
  EXPECT_DOUBLE_EQ(b.msPerSegment(3), render::TractBudget::kInitialMsPerSegment);
  b.measured(0, 10'000, 10.0); // 1 us per segment at level 0
  EXPECT_DOUBLE_EQ(b.msPerSegment(0), 1e-3);
  EXPECT_DOUBLE_EQ(b.msPerSegment(2), 1e-3) << "an unmeasured level borrows the nearest measured cost";
  EXPECT_EQ(b.chunk(), 20'000u);
  b.measured(2, 10'000, 30.0); // coarse segments cost more (longer: more fragments)
  EXPECT_DOUBLE_EQ(b.msPerSegment(2), 3e-3);
  EXPECT_DOUBLE_EQ(b.msPerSegment(1), 3e-3) << "the coarser neighbour wins a tie";
  b.measured(2, 10'000, 10.0);
  EXPECT_DOUBLE_EQ(b.msPerSegment(2), 2e-3) << "halfway towards the new sample";
  // Tiny draws and bad timings are ignored.
  b.measured(2, 10, 1000.0);
  b.measured(2, 10'000, 0.0);
  b.measured(2, 10'000, std::nan(""));
  b.measured(-1, 10'000, 5.0);
  EXPECT_DOUBLE_EQ(b.msPerSegment(2), 2e-3);
  EXPECT_EQ(b.chunk(), 20'000u);
  // Levels of 100k, 50k, 25k, 12.5k segments at 1, 2 (borrowed from level 2), 2 and 4 us each.
  b.measured(3, 10'000, 40.0);
  const std::size_t levels[] = {100'000, 50'000, 25'000, 12'500};
  // 20 ms: none fits whole (100, 100, 50, 50 ms); level 2's 10k of 25k segments (40%) beat level 3's 5k of
  // 12.5k (40%, not clearly more) and level 0's 20k of 100k (20%).
  auto c = b.choose(levels);
  EXPECT_EQ(c.level, 2);
  EXPECT_EQ(c.segments, 10'000u);
  // 60 ms: level 2 fits whole (50 ms); level 1 (100 ms) does not.
  render::TractBudget wide(60.0);
  wide.measured(0, 10'000, 10.0);
  wide.measured(2, 10'000, 20.0);
  c = wide.choose(levels);
  EXPECT_EQ(c.level, 2);
  EXPECT_EQ(c.segments, 25'000u);
  EXPECT_EQ(render::TractBudget().choose(std::span<const std::size_t>()).segments, 0u);
}
