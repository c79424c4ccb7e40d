// SPDX-License-Identifier: GPL-3.0-or-later
// CPU side of the tract overlay: display decimation (render/tract_renderer.h) and the near-surface
// selection (surfaces/analyses/near_surface.h) on a plane, where the distance to the surface is |z|.
#include "io/formats/tensor_io.h"
#include "render/reference/scenes.h"
#include "render/tract_renderer.h"
#include "support/polylines.h"
#include "support/test_env.h"
#include "surfaces/analyses/near_surface.h"
#include "surfaces/selection/tract_selection.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tract_files.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace dtf;
using dtf::test::gridLines;

namespace {

void expectEndpointsKept(const Polylines& in, const Polylines& out) {
  ASSERT_EQ(out.lineCount(), in.lineCount());
  for (std::size_t l = 0; l < in.lineCount(); ++l) {
    EXPECT_EQ(out.points[out.offsets[l]], in.points[in.offsets[l]]);
    EXPECT_EQ(out.points[out.offsets[l + 1] - 1], in.points[in.offsets[l + 1] - 1]);
  }
}

} // namespace

TEST(TractDecimation, KeepsEndpointsAndStaysUnderTheCap) {
  const Polylines in = gridLines(1000, 1500); // 1.5M points
  const Polylines out = render::decimateForDisplay(in);
  EXPECT_LE(out.points.size(), render::kTractDisplayPointCap);
  EXPECT_GT(out.points.size(), render::kTractDisplayPointCap / 2);
  expectEndpointsKept(in, out);
  const Polylines small = gridLines(3, 1234);
  for (std::size_t cap : {24u, 1001u, 12345u}) { // every line fits at kMinDisplayLinePoints points
    SCOPED_TRACE(cap);
    const Polylines o = render::decimateForDisplay(small, cap);
    EXPECT_LE(o.points.size(), cap);
    expectEndpointsKept(small, o);
  }
  // Under 24 points one line is kept with as many points as fit, not three chords.
  const Polylines one = render::decimateForDisplay(small, 7);
  ASSERT_EQ(one.lineCount(), 1u);
  EXPECT_EQ(one.points.size(), 7u);
  EXPECT_EQ(one.points.back(), small.points[1233]);
}

TEST(TractDecimation, UnderTheCapNothingChangesAndTooManyLinesAreThinned) {
  const Polylines in = gridLines(10, 50);
  const Polylines same = render::decimateForDisplay(in, 500);
  EXPECT_EQ(same.points, in.points);
  EXPECT_EQ(same.offsets, in.offsets);
  // 101 lines at 8 points each need 808: every 39th line is kept (0, 39, 78), each at 6 of its 10 points
  // (every 2nd and the last), 18 points under the cap of 21, rather than 10 chords.
  const Polylines thin = render::decimateForDisplay(gridLines(101, 10), 21);
  ASSERT_EQ(thin.lineCount(), 3u);
  for (std::size_t l = 0; l < thin.lineCount(); ++l) {
    EXPECT_EQ(thin.offsets[l + 1] - thin.offsets[l], 6u);
    EXPECT_EQ(thin.points[thin.offsets[l]].y, 39.0f * static_cast<float>(l));
  }
}

TEST(TractDecimation, PastTheCapLinesKeepTheirShape) {
  // 1000 lines of 50 points under a cap of 4000: every other line at 8 points (the 1st, every 7th, the last)
  // instead of 2000 two-point chords.
  const Polylines in = gridLines(1000, 50);
  const Polylines out = render::decimateForDisplay(in, 4000);
  ASSERT_EQ(out.lineCount(), 500u);
  EXPECT_EQ(out.points.size(), 4000u);
  for (std::size_t l = 0; l < out.lineCount(); ++l) {
    ASSERT_EQ(out.offsets[l + 1] - out.offsets[l], render::kMinDisplayLinePoints);
    EXPECT_EQ(out.points[out.offsets[l]].y, 2.0f * static_cast<float>(l));
    EXPECT_EQ(out.points[out.offsets[l] + 1].x, 7.0f);
    EXPECT_EQ(out.points[out.offsets[l + 1] - 1].x, 49.0f);
  }
  // Whole lines (for the near-surface rule): every 13th line, each with all its 50 points.
  std::vector<std::uint32_t> every(1000);
  for (std::uint32_t i = 0; i < 1000; ++i)
    every[i] = i;
  const Polylines whole = render::decimateForDisplay(in, every, 4000, render::kWholeDisplayLines);
  ASSERT_EQ(whole.lineCount(), 77u);
  EXPECT_EQ(whole.points.size(), 77u * 50u);
  for (std::size_t l = 0; l < whole.lineCount(); ++l) {
    EXPECT_EQ(whole.offsets[l + 1] - whole.offsets[l], 50u);
    EXPECT_EQ(whole.points[whole.offsets[l]].y, 13.0f * static_cast<float>(l));
  }
  // Two-point lines only when even one short line per kept line exceeds the cap: 5000 lines, cap 1000.
  const Polylines chords = render::decimateForDisplay(gridLines(5000, 50), 1000);
  EXPECT_LE(chords.points.size(), 1000u);
  EXPECT_EQ(chords.lineCount(), 125u);
}

TEST(TractDecimation, OfSelectedLinesIsTheDecimatedSubsetWithValuesAndGroups) {
  Polylines in = gridLines(60, 30);
  for (std::size_t l = 0; l < 60; ++l)
    in.offsets[l + 1] = static_cast<std::uint32_t>(30 * (l + 1)); // same layout, made explicit
  TractValues id{"id", 1, {}}, xy{"xy", 2, {}};
  for (std::size_t l = 0; l < 60; ++l)
    id.values.push_back(static_cast<float>(l));
  for (const glm::vec3& p : in.points)
    xy.values.insert(xy.values.end(), {p.x, p.y});
  in.perLine.push_back(id);
  in.perPoint.push_back(xy);
  TractGroup even{"even", {}}, first{"first", {}};
  for (std::uint32_t l = 0; l < 60; l += 2)
    even.lines.push_back(l);
  for (std::uint32_t l = 0; l < 10; ++l)
    first.lines.push_back(l);
  in.groups = {even, first};
  std::vector<std::uint32_t> keep;
  for (std::uint32_t l = 1; l < 60; l += 3)
    keep.push_back(l); // 1, 4, 7, ..., 58
  keep.push_back(59);
  for (std::size_t cap : {100000u, 300u, 40u, 5u}) {
    SCOPED_TRACE(cap);
    const Polylines direct = render::decimateForDisplay(in, keep, cap);
    const Polylines viaSubset = render::decimateForDisplay(surfaces::subsetWithGroups(in, keep), cap);
    EXPECT_LE(direct.points.size(), cap);
    EXPECT_GT(direct.lineCount(), 0u);
    EXPECT_EQ(direct.points, viaSubset.points);
    EXPECT_EQ(direct.offsets, viaSubset.offsets);
    ASSERT_EQ(direct.perPoint.size(), 1u);
    EXPECT_EQ(direct.perPoint[0].values, viaSubset.perPoint[0].values);
    EXPECT_EQ(direct.perPoint[0].values.size(), 2 * direct.points.size());
    ASSERT_EQ(direct.perLine.size(), 1u);
    EXPECT_EQ(direct.perLine[0].values, viaSubset.perLine[0].values);
    ASSERT_EQ(direct.groups.size(), 2u);
    for (std::size_t g = 0; g < 2; ++g) {
      EXPECT_EQ(direct.groups[g].name, in.groups[g].name);
      EXPECT_EQ(direct.groups[g].lines, viaSubset.groups[g].lines);
      for (std::uint32_t line : direct.groups[g].lines) { // each member really is in the source group
        const auto source = static_cast<std::uint32_t>(direct.perLine[0].values[line]);
        EXPECT_TRUE(g == 0 ? source % 2 == 0 : source < 10) << source;
      }
    }
  }
  // Without thinning every kept line is there in full.
  const Polylines all = render::decimateForDisplay(in, keep, 100000);
  EXPECT_EQ(all.lineCount(), keep.size());
  EXPECT_EQ(all.points.size(), 30 * keep.size());
}

TEST(TractSelection, KeepsExactlyTheSegmentsWithinDOfAPlane) {
  const Mesh plane = render::reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 100, 100, 4);
  const surfaces::DistanceQuery query(plane);
  // Distance |z|; D = 2.5: near flags 1 1 1 0 1 1 0 1 1 0 -> runs [0, 2], [4, 5], [7, 8].
  const float z[] = {0, 1, -2, 3, 2, -1, 5, 0.5f, 0.2f, -2.6f};
  Polylines in;
  in.offsets = {0};
  for (int i = 0; i < 10; ++i)
    in.points.emplace_back(float(i), 0.0f, z[i]);
  in.offsets.push_back(10);
  // A second line entirely far away, a third entirely near.
  in.points.emplace_back(0, 5, 10);
  in.points.emplace_back(1, 5, 11);
  in.offsets.push_back(12);
  in.points.emplace_back(0, 9, 0.1f);
  in.points.emplace_back(3, 9, -0.1f);
  in.offsets.push_back(14);
  for (const bool exhaustive : {false, true}) {
    SCOPED_TRACE(exhaustive);
    surfaces::NearSurfaceOptions o;
    o.exhaustive = exhaustive;
    const Polylines out = surfaces::selectNearSurface(in, query, 2.5, o);
    ASSERT_EQ(out.lineCount(), 4u);
    EXPECT_EQ(out.offsets, (std::vector<std::uint32_t>{0, 3, 5, 7, 9}));
    const std::vector<std::size_t> from = {0, 1, 2, 4, 5, 7, 8, 12, 13};
    for (std::size_t i = 0; i < from.size(); ++i)
      EXPECT_EQ(out.points[i], in.points[from[i]]) << i;
  }
  const Polylines all = surfaces::selectNearSurface(in, query, 0.0);
  EXPECT_EQ(all.points, in.points);
}

TEST(TractSelection, MeshPlaneFindsSlicesAndRejectsCurvedMeshes) {
  const auto p =
      surfaces::meshPlane(render::reference::planeMesh({0, 0, 7}, {1, 0, 0}, {0, 1, 0}, 10, 10, 3));
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(std::abs(p->z), 1.0f, 1e-6f);
  EXPECT_NEAR(p->w / p->z, -7.0f, 1e-5f);
  EXPECT_FALSE(surfaces::meshPlane(render::reference::uvSphere({0, 0, 0}, 10, 8, 8)).has_value());
}

namespace {

// Per point of `lines`: kept by the selection `sel` (its points are copies, in order).
std::vector<char> keptFlags(const Polylines& lines, const Polylines& sel) {
  std::vector<char> kept(lines.points.size(), 0);
  std::size_t j = 0;
  for (std::size_t i = 0; i < lines.points.size() && j < sel.points.size(); ++i)
    if (lines.points[i] == sel.points[j]) {
      kept[i] = 1;
      ++j;
    }
  EXPECT_EQ(j, sel.points.size()) << "the selection is not an ordered subset of the input";
  return kept;
}

// The bounded, prefiltered, threaded selection equals one exact query per point, except where a point lies
// within 1e-4 mm of the limit (float rounding of the bounds).
void expectSameAsExhaustive(const Polylines& lines, const Mesh& mesh, double maxMm) {
  const surfaces::DistanceQuery query(mesh);
  surfaces::NearSurfaceOptions exhaustive;
  exhaustive.exhaustive = true;
  const Polylines ref = surfaces::selectNearSurface(lines, query, maxMm, exhaustive);
  ASSERT_GT(ref.points.size(), 100u);
  ASSERT_LT(ref.points.size(), lines.points.size());
  for (int threads : {1, 3}) {
    SCOPED_TRACE(threads);
    surfaces::NearSurfaceOptions fast;
    fast.threads = threads;
    const Polylines sel = surfaces::selectNearSurface(lines, query, maxMm, fast);
    if (sel.points == ref.points && sel.offsets == ref.offsets) continue;
    const auto a = keptFlags(lines, ref), b = keptFlags(lines, sel);
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i] != b[i]) {
        EXPECT_NEAR(query.distance(lines.points[i]), maxMm, 1e-4) << "point " << i;
      }
  }
}

} // namespace

TEST(TractSelection, FastPathEqualsExhaustiveQueriesOnASphere) {
  // Helices winding in and out of a sphere of radius 20: near, far and crossing runs.
  Polylines l;
  l.offsets = {0};
  for (int i = 0; i < 300; ++i) {
    const float a = 0.021f * float(i), b = 0.37f * float(i);
    for (int k = 0; k < 200; ++k) {
      const float t = float(k) / 199.0f, r = 14.0f + 12.0f * std::sin(7.0f * t + a);
      l.points.emplace_back(r * std::cos(b + 3 * t), r * std::sin(b + 3 * t), 40.0f * t - 20.0f);
    }
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  expectSameAsExhaustive(l, render::reference::uvSphere({0, 0, 0}, 20, 48, 24), 3.0);
}

TEST(TractSelection, FastPathEqualsExhaustiveQueriesOnTheBrain) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const TensorField field = io::readTensorVolume(tensor.string()).field;
  const Mesh fa = session::buildSurface(session::parseSurfaceSpec("fa=0.25"), field, computeFaMap(field));
  expectSameAsExhaustive(session::readTracts(tck.string()), fa, 3.0);
}

TEST(TractSelection, CancelledSelectionIsEmpty) {
  const Mesh plane = render::reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 100, 100, 4);
  const surfaces::DistanceQuery query(plane);
  std::atomic<bool> cancel{true};
  surfaces::NearSurfaceOptions o;
  o.cancel = &cancel;
  const Polylines out = surfaces::selectNearSurface(gridLines(200, 20), query, 1.0, o);
  EXPECT_EQ(out.lineCount(), 0u);
  cancel = false;
  EXPECT_EQ(surfaces::selectNearSurface(gridLines(200, 20), query, 1.0, o).lineCount(),
            52u); // y = 0 .. 51 (the plane ends at 50)
}

// Positions only and at least 200 k points out: the lines are copied on two threads, each into the place its
// size gives it. Whole lines equal Polylines::subset; decimated ones hold every step-th point and the last.
TEST(TractDecimation, TheParallelCopyPutsEveryLineInItsPlace) {
  const Polylines in = gridLines(4001, 200);
  std::vector<std::uint32_t> keep;
  for (std::uint32_t l = 0; l < 4001; l += 2)
    keep.push_back(l); // 2001 lines, 400200 points
  const Polylines whole = render::decimateForDisplay(in, keep);
  const Polylines reference = in.subset(keep);
  EXPECT_EQ(whole.offsets, reference.offsets);
  EXPECT_TRUE(whole.points == reference.points);
  // A cap of 250 k: every line (2001 * 8 points fit) at every 2nd point and the last, 101 points each.
  const Polylines thin = render::decimateForDisplay(in, keep, 250'000);
  EXPECT_LE(thin.points.size(), 250'000u);
  EXPECT_GE(thin.points.size(), 200'000u) << "the parallel path is taken";
  ASSERT_EQ(thin.lineCount(), keep.size());
  const std::size_t n = 101, step = 2;
  for (std::size_t l = 0; l < thin.lineCount(); ++l) {
    ASSERT_EQ(thin.offsets[l + 1] - thin.offsets[l], n);
    for (std::size_t i = 0; i + 1 < n; ++i)
      ASSERT_EQ(thin.points[thin.offsets[l] + i], glm::vec3(float(i * step), float(keep[l]), 0)) << l << " " << i;
    EXPECT_EQ(thin.points[thin.offsets[l + 1] - 1], glm::vec3(199, float(keep[l]), 0));
  }
}
