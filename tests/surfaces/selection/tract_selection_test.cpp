// SPDX-License-Identifier: GPL-3.0-or-later
// ROI selection: tckedit's rules on lines whose answers are known by construction (spheres, boxes, masks on
// another grid, includes, excludes, ordered includes, end points, segments between vertices, length), and
// the indexed route against the vertex walk on random tractograms and random region sets.
#include "surfaces/selection/tract_selection.h"

#include "io/model/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace dtf;
using namespace dtf::surfaces;

namespace {

Polylines linesOf(const std::vector<std::vector<glm::vec3>>& lines) {
  Polylines p;
  p.offsets.push_back(0);
  for (const auto& l : lines) {
    p.points.insert(p.points.end(), l.begin(), l.end());
    p.offsets.push_back(static_cast<std::uint32_t>(p.points.size()));
  }
  return p;
}

// A straight line from a to b with n vertices.
std::vector<glm::vec3> straight(glm::vec3 a, glm::vec3 b, int n) {
  std::vector<glm::vec3> v;
  for (int k = 0; k < n; ++k)
    v.push_back(a + (b - a) * (static_cast<float>(k) / static_cast<float>(n - 1)));
  return v;
}

Region sphere(RegionKind kind, glm::dvec3 c, double r) {
  Region g;
  g.kind = kind;
  g.shape = RegionShape::Sphere;
  g.centre = c;
  g.radius = r;
  g.name = "s";
  return g;
}

Region box(RegionKind kind, glm::dvec3 lo, glm::dvec3 hi) {
  Region g;
  g.kind = kind;
  g.shape = RegionShape::Box;
  g.lo = lo;
  g.hi = hi;
  g.name = "b";
  return g;
}

std::vector<std::uint32_t> select(const Polylines& p, const RegionSet& set, bool indexed) {
  const TractView v = viewOf(p);
  RegionTester t(set);
  if (!indexed) return selectLines(v, t);
  TractIndex index(v, 4.0);
  return selectLines(v, t, &index);
}

// Both routes, which must agree.
std::vector<std::uint32_t> both(const Polylines& p, const RegionSet& set) {
  const auto a = select(p, set, false), b = select(p, set, true);
  EXPECT_EQ(a, b) << "the index and the walk disagree";
  return a;
}

using Ids = std::vector<std::uint32_t>;

} // namespace

TEST(TractSelection, SphereIncludesAVertexAtTheRadiusAndNotJustBeyond) {
  // Vertices at x = -10 .. 10 step 1 along y = 0, z = 0 (line 0) and along y = 3 (line 1).
  const Polylines p = linesOf({straight({-10, 0, 0}, {10, 0, 0}, 21), straight({-10, 3, 0}, {10, 3, 0}, 21)});
  RegionSet set;
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, 3.0)};
  EXPECT_EQ(both(p, set), (Ids{0, 1})); // (0,3,0) lies at distance 3 exactly
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, 2.99)};
  EXPECT_EQ(both(p, set), (Ids{0}));
}

TEST(TractSelection, IncludesAreAndedAndExcludesOred) {
  const Polylines p = linesOf({straight({-10, 0, 0}, {10, 0, 0}, 21),   // through A and B
                               straight({-10, 0, 0}, {-1, 0, 0}, 10),   // A only
                               straight({-10, 0, 5}, {10, 0, 5}, 21),   // through A, B and C? no: z = 5
                               straight({0, -10, 0}, {0, 10, 0}, 21)}); // through the middle only
  const Region A = sphere(RegionKind::Include, {-8, 0, 0}, 1.5), B = sphere(RegionKind::Include, {8, 0, 0}, 1.5);
  RegionSet set;
  set.regions = {A, B};
  EXPECT_EQ(both(p, set), (Ids{0}));
  set.regions = {A};
  EXPECT_EQ(both(p, set), (Ids{0, 1}));
  set.regions = {A, sphere(RegionKind::Exclude, {0, 0, 0}, 0.5)};
  EXPECT_EQ(both(p, set), (Ids{1}));
  // Excludes only: everything that misses them.
  set.regions = {sphere(RegionKind::Exclude, {0, 0, 0}, 0.5), sphere(RegionKind::Exclude, {0, 0, 5}, 0.5)};
  EXPECT_EQ(both(p, set), (Ids{1}));
}

TEST(TractSelection, OrderedIncludesMustBeEnteredInOrderAlongTheStoredVertices) {
  const glm::vec3 a{-8, 0, 0}, b{8, 0, 0};
  const Polylines p = linesOf({straight(a, b, 17),                     // A then B
                               straight(b, a, 17),                     // B then A
                               [&] {                                   // A, B, then back into A
                                 auto v = straight(a, b, 17);
                                 auto w = straight(b, a, 17);
                                 v.insert(v.end(), w.begin() + 1, w.end());
                                 return v;
                               }(),
                               straight({-8, 0, 0}, {-8, 5, 0}, 6)}); // A only
  RegionSet set;
  set.regions = {sphere(RegionKind::IncludeOrdered, a, 1.5), sphere(RegionKind::IncludeOrdered, b, 1.5)};
  // tckedit: re-entering an earlier region after a later one breaks the order.
  EXPECT_EQ(both(p, set), (Ids{0}));
  std::swap(set.regions[0], set.regions[1]);
  EXPECT_EQ(both(p, set), (Ids{1}));
  // Unordered, the first three pass.
  for (auto& r : set.regions)
    r.kind = RegionKind::Include;
  EXPECT_EQ(both(p, set), (Ids{0, 1, 2}));
}

TEST(TractSelection, EndsOnlyTestsTheTwoEndPoints) {
  const Polylines p = linesOf({straight({-10, 0, 0}, {10, 0, 0}, 21),  // passes through the origin
                               straight({0, 0, 0}, {10, 0, 0}, 11),    // starts there
                               straight({10, 0, 0}, {0, 0, 0}, 11)});  // ends there
  RegionSet set;
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, 1.0)};
  EXPECT_EQ(both(p, set), (Ids{0, 1, 2}));
  set.endsOnly = true;
  EXPECT_EQ(both(p, set), (Ids{1, 2}));
  // An exclude region on the way is ignored with ends only.
  set.regions = {sphere(RegionKind::Include, {10, 0, 0}, 1.0), sphere(RegionKind::Exclude, {5, 0, 0}, 1.0)};
  EXPECT_EQ(both(p, set), (Ids{0, 1, 2}));
  set.endsOnly = false;
  EXPECT_EQ(both(p, set), (Ids{}));
}

TEST(TractSelection, PreciseCatchesARegionCrossedBetweenTwoVertices) {
  // Two vertices 10 mm apart around a 1 mm sphere and a thin box; a line that passes 1.5 mm away.
  const Polylines p = linesOf({{{-5, 0, 0}, {5, 0, 0}}, {{-5, 1.5f, 0}, {5, 1.5f, 0}}});
  RegionSet set;
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, 1.0)};
  EXPECT_EQ(both(p, set), (Ids{}));
  set.precise = true;
  EXPECT_EQ(both(p, set), (Ids{0}));
  set.regions = {box(RegionKind::Include, {-0.1, -0.1, -0.1}, {0.1, 2, 0.1})};
  EXPECT_EQ(both(p, set), (Ids{0, 1}));
  set.regions.front().kind = RegionKind::Exclude;
  EXPECT_EQ(both(p, set), (Ids{}));
}

TEST(TractSelection, PreciseOrdersRegionsByWhereTheSegmentEntersThem) {
  // One segment from x = -5 to 5 crosses A (x = -2) then B (x = 2): ordered A, B passes; B, A does not.
  const Polylines p = linesOf({{{-5, 0, 0}, {5, 0, 0}}});
  RegionSet set;
  set.precise = true;
  set.regions = {sphere(RegionKind::IncludeOrdered, {-2, 0, 0}, 0.5), sphere(RegionKind::IncludeOrdered, {2, 0, 0}, 0.5)};
  EXPECT_EQ(both(p, set), (Ids{0}));
  std::swap(set.regions[0], set.regions[1]);
  EXPECT_EQ(both(p, set), (Ids{}));
}

TEST(TractSelection, BoxHoldsItsFacesAndNothingBeyond) {
  const Polylines p = linesOf({{{1, 1, 1}}, {{2, 1, 1}}, {{2.001f, 1, 1}}, {{0, 0, 0}, {1, 2, 3}}});
  RegionSet set;
  set.regions = {box(RegionKind::Include, {0, 0, 0}, {2, 2, 2})};
  EXPECT_EQ(both(p, set), (Ids{0, 1, 3}));
}

TEST(TractSelection, MaskOnAnotherGridUsesTheVoxelEachVertexRoundsTo) {
  // A 2 mm LAS grid (x flipped) shifted by (10, -4, 2); voxel (3, 2, 1) is the only one inside.
  auto mask = std::make_shared<MaskVolume>();
  glm::dmat4 A(1.0);
  A[0][0] = -2.0;
  A[1][1] = 2.0;
  A[2][2] = 2.0;
  A[3] = glm::dvec4(10, -4, 2, 1);
  mask->grid = Grid::fromAffine({6, 5, 4}, A);
  mask->data.assign(mask->grid.voxelCount(), 0);
  mask->data[mask->grid.index(3, 2, 1)] = 1;
  const glm::dvec3 c = mask->grid.toWorld({3, 2, 1}); // (4, 0, 4)
  Region m;
  m.shape = RegionShape::Mask;
  m.mask = mask;
  m.name = "mask";
  RegionSet set;
  set.regions = {m};
  const glm::vec3 cf(c);
  const Polylines p = linesOf({{cf + glm::vec3(0.9f, -0.9f, 0.9f)}, // within the voxel's cell (half a voxel = 1 mm)
                               {cf + glm::vec3(1.1f, 0, 0)},         // rounds into the next voxel
                               {cf + glm::vec3(0, 0, -1.1f)},
                               // a segment that crosses the cell between two far vertices
                               {cf + glm::vec3(-5, 0.2f, 0.3f), cf + glm::vec3(5, 0.2f, 0.3f)}});
  EXPECT_EQ(both(p, set), (Ids{0}));
  set.precise = true;
  EXPECT_EQ(both(p, set), (Ids{0, 3}));
  EXPECT_NEAR(m.centreOf().x, c.x, 1e-9);
}

TEST(TractSelection, LengthRangeKeepsLinesWithinIt) {
  const Polylines p = linesOf({straight({0, 0, 0}, {10, 0, 0}, 11), straight({0, 0, 0}, {30, 0, 0}, 31),
                               straight({0, 0, 0}, {50, 0, 0}, 51)});
  RegionSet set;
  set.minLengthMm = 20;
  set.maxLengthMm = 40;
  EXPECT_EQ(both(p, set), (Ids{1}));
  set.minLengthMm = 10; // inclusive
  set.maxLengthMm = 30;
  EXPECT_EQ(both(p, set), (Ids{0, 1}));
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, 1)};
  EXPECT_EQ(both(p, set), (Ids{0, 1}));
}

TEST(TractSelection, BadRegionsAreRefusedWithTheirName) {
  RegionSet set;
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, std::nan(""))};
  EXPECT_THROW(RegionTester{set}, InputError);
  set.regions = {sphere(RegionKind::Include, {0, 0, 0}, -1)};
  EXPECT_THROW(RegionTester{set}, InputError);
  set.regions = {box(RegionKind::Include, {0, 0, 0}, {1, -1, 1})};
  try {
    RegionTester t(set);
    FAIL() << "an inverted box was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
  auto mask = std::make_shared<MaskVolume>();
  mask->grid = Grid::fromAffine({2, 2, 2}, glm::dmat4(0.0));
  mask->data.assign(8, 1);
  Region m;
  m.shape = RegionShape::Mask;
  m.mask = mask;
  set.regions = {m};
  EXPECT_THROW(RegionTester{set}, InputError);
  set.regions.clear();
  set.minLengthMm = 10;
  set.maxLengthMm = 5;
  EXPECT_THROW(RegionTester{set}, InputError);
}

TEST(TractSelection, SubsetKeepsDataAndRenumbersGroups) {
  Polylines p = linesOf({straight({0, 0, 0}, {1, 0, 0}, 2), straight({0, 0, 0}, {2, 0, 0}, 3),
                         straight({0, 0, 0}, {3, 0, 0}, 4)});
  p.perLine.push_back({"w", 1, {1, 2, 3}});
  p.perPoint.push_back({"v", 1, {0, 1, 2, 3, 4, 5, 6, 7, 8}});
  p.groups.push_back({"g", {0, 2}});
  const Polylines s = subsetWithGroups(p, {1, 2});
  ASSERT_EQ(s.lineCount(), 2u);
  EXPECT_EQ(s.perLine[0].values, (std::vector<float>{2, 3}));
  EXPECT_EQ(s.perPoint[0].values, (std::vector<float>{2, 3, 4, 5, 6, 7, 8}));
  ASSERT_EQ(s.groups.size(), 1u);
  EXPECT_EQ(s.groups[0].lines, (std::vector<std::uint32_t>{1}));
  EXPECT_TRUE(s.inconsistency().empty()) << s.inconsistency();
}

// Random smooth lines in a 100 mm cube and random region sets: the index's answer equals the walk's, and
// each region's hits equal a brute-force scan.
TEST(TractSelection, IndexAgreesWithTheWalkOnRandomTractograms) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<std::vector<glm::vec3>> lines;
  for (int i = 0; i < 3000; ++i) {
    glm::vec3 p(U(rng) * 100, U(rng) * 100, U(rng) * 100), d(U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f);
    std::vector<glm::vec3> l;
    const int n = 1 + static_cast<int>(U(rng) * 40);
    const float step = i % 50 == 0 ? 30.0f : 2.0f; // a few lines with long segments (oversized chunks)
    for (int k = 0; k < n; ++k) {
      l.push_back(p);
      d = glm::normalize(d + 0.3f * glm::vec3(U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f));
      p += step * d;
    }
    lines.push_back(l);
  }
  const Polylines p = linesOf(lines);
  const TractView v = viewOf(p);
  TractIndex index(v, 0.0);
  auto mask = std::make_shared<MaskVolume>();
  mask->grid = Grid::fromAffine({20, 20, 20}, glm::dmat4(glm::dvec4(3, 0.5, 0, 0), glm::dvec4(-0.5, 3, 0, 0),
                                                       glm::dvec4(0, 0, 3, 0), glm::dvec4(20, 10, 15, 1)));
  mask->data.assign(mask->grid.voxelCount(), 0);
  for (int k = 5; k < 9; ++k)
    for (int j = 3; j < 12; ++j)
      for (int i = 7; i < 10; ++i)
        mask->at(i, j, k) = 1;
  std::size_t nonEmpty = 0;
  for (int trial = 0; trial < 60; ++trial) {
    RegionSet set;
    set.precise = trial % 3 == 0;
    const int n = 1 + trial % 3;
    for (int r = 0; r < n; ++r) {
      const RegionKind kind = static_cast<RegionKind>((trial + r) % 3);
      const int shape = (trial / 3 + r) % 3;
      const glm::dvec3 c(U(rng) * 100, U(rng) * 100, U(rng) * 100);
      if (shape == 0) set.regions.push_back(sphere(kind, c, 5 + 15 * U(rng)));
      if (shape == 1) set.regions.push_back(box(kind, c, c + glm::dvec3(5 + 20 * U(rng), 5 + 20 * U(rng), 10)));
      if (shape == 2) {
        Region m;
        m.kind = kind;
        m.shape = RegionShape::Mask;
        m.mask = mask;
        set.regions.push_back(m);
      }
    }
    RegionTester t(set);
    const auto walked = selectLines(v, t);
    SelectionStats st;
    const auto indexed = selectLines(v, t, &index, 0, &st);
    EXPECT_EQ(walked, indexed) << "trial " << trial;
    nonEmpty += !walked.empty();
    for (std::size_t r = 0; r < set.regions.size(); ++r) {
      Ids brute;
      for (std::size_t i = 0; i < v.lineCount; ++i)
        if (t.touches(r, v.points + v.begin(i), v.size(i))) brute.push_back(static_cast<std::uint32_t>(i));
      EXPECT_EQ(index.linesTouching(t, r), brute) << "trial " << trial << " region " << r;
    }
  }
  EXPECT_GT(nonEmpty, 20u) << "the random region sets select too little to test anything";
}

// A view with separators between lines (.tck's NaN triplets) selects as the same lines without them.
TEST(TractSelection, ViewWithSeparatorsSelectsTheSameLines) {
  const std::vector<std::vector<glm::vec3>> lines = {straight({-10, 0, 0}, {10, 0, 0}, 21),
                                                     straight({-10, 5, 0}, {10, 5, 0}, 21)};
  std::vector<glm::vec3> pts;
  std::vector<std::uint64_t> starts;
  for (const auto& l : lines) {
    starts.push_back(pts.size());
    pts.insert(pts.end(), l.begin(), l.end());
    pts.push_back(glm::vec3(std::nanf("")));
  }
  starts.push_back(pts.size());
  TractView v;
  v.points = pts.data();
  v.starts64 = starts.data();
  v.lineCount = 2;
  v.gap = 1;
  EXPECT_EQ(v.pointCount(), 42u);
  RegionSet set;
  set.regions = {sphere(RegionKind::Include, {10, 5, 0}, 0.5)};
  RegionTester t(set);
  TractIndex index(v);
  EXPECT_EQ(selectLines(v, t), (Ids{1}));
  EXPECT_EQ(selectLines(v, t, &index), (Ids{1}));
  EXPECT_NEAR(lineLength(v, 1), 20.0, 1e-5);
}
