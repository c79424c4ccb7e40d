// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric select` as a user runs it: the same streamlines as MRtrix's tckedit on the real tracts of the
// shared data for each kind of region tckedit has (spheres, includes and excludes, ordered includes, end
// points, masks on another grid, atlas labels as the mask of one label), boxes against a brute-force count,
// region set files against the same flags, several inputs, TRX groups and values kept, --as-group, and
// targeted tracking (`track --include`) giving streamlines that all pass the region.
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"
#include "support/chromium.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>

namespace fs = std::filesystem;
using dtf::test::runDtfabric;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// tckedit on one thread (its output order is then the input order).
int runTckedit(const fs::path& in, const fs::path& out, const std::string& args) {
  const std::string cmd = "tckedit " + q(in) + " " + q(out) + " " + args + " -nthreads 0 -force -quiet";
  return std::system(cmd.c_str());
}

// The streamlines of two files are the same, in the same order, point for point.
void expectSameLines(const fs::path& a, const fs::path& b, const std::string& what) {
  const dtf::Polylines x = dtf::io::readTck(a.string()), y = dtf::io::readTck(b.string());
  ASSERT_EQ(x.lineCount(), y.lineCount()) << what;
  ASSERT_EQ(x.points.size(), y.points.size()) << what;
  EXPECT_EQ(x.offsets, y.offsets) << what;
  for (std::size_t i = 0; i < x.points.size(); ++i)
    if (x.points[i] != y.points[i]) {
      ADD_FAILURE() << what << ": point " << i << " differs";
      break;
    }
}

// A mask or label image on a grid of its own: 2 mm voxels, x flipped (LAS) and turned 10 degrees about z.
dtf::ScalarVolume obliqueVolume() {
  const double a = 10.0 * M_PI / 180.0;
  glm::dmat4 A(1.0);
  A[0] = glm::dvec4(-2 * std::cos(a), -2 * std::sin(a), 0, 0);
  A[1] = glm::dvec4(-2 * std::sin(a), 2 * std::cos(a), 0, 0);
  A[2] = glm::dvec4(0, 0, 2, 0);
  A[3] = glm::dvec4(40, -20, 10, 1);
  dtf::ScalarVolume v;
  v.grid = dtf::Grid::fromAffine({40, 50, 40}, A);
  v.data.assign(v.grid.voxelCount(), 0.0f);
  return v;
}

// Sets voxels within `r` mm of world point `c` to `value`.
void ball(dtf::ScalarVolume& v, glm::dvec3 c, double r, float value) {
  for (int k = 0; k < v.grid.dims.z; ++k)
    for (int j = 0; j < v.grid.dims.y; ++j)
      for (int i = 0; i < v.grid.dims.x; ++i)
        if (glm::length(v.grid.toWorld({i, j, k}) - c) <= r) v.data[v.grid.index(i, j, k)] = value;
}

// Points on the right corticospinal tract (voxel 30,34,15 of the bundled brain) and higher in the corona
// radiata, the body of the corpus callosum (voxel 33,42,22) and the midline above it.
const std::string kCstLow = "18,3.7,21.6,6", kCstHigh = "20,0,45,10", kCc = "9,27.7,42.6,6",
                  kMidline = "0,27.7,42.6,4";

} // namespace

TEST(SelectCli, SameStreamlinesAsTckeditForEachKindOfRegion) {
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_REQUIRE_TOOL("tckedit");
  const fs::path dir = dtf::test::scratchDir();
  dtf::ScalarVolume mask = obliqueVolume(), labels = obliqueVolume(), label7 = obliqueVolume();
  ball(mask, {0, 27.7, 42.6}, 7, 1.0f);
  ball(labels, {-18, 3.7, 21.6}, 7, 3.0f);
  ball(labels, {18, 3.7, 21.6}, 7, 7.0f);
  ball(label7, {18, 3.7, 21.6}, 7, 1.0f);
  dtf::io::writeScalarVolume((dir / "mask.nii.gz").string(), mask);
  dtf::io::writeScalarVolume((dir / "labels.nii.gz").string(), labels);
  dtf::io::writeScalarVolume((dir / "label7.nii.gz").string(), label7);
  const std::string m = q(dir / "mask.nii.gz");
  struct Case {
    std::string name, ours, theirs;
    std::size_t atLeast; // a selection too small to mean anything would not test the rule
  };
  const std::vector<Case> cases = {
      {"two spheres", "--include " + kCstLow + " --include " + kCstHigh,
       "-include " + kCstLow + " -include " + kCstHigh, 20},
      {"include and exclude", "--include " + kCc + " --exclude " + kMidline,
       "-include " + kCc + " -exclude " + kMidline, 5},
      {"ordered", "--include-ordered " + kCstLow + " --include-ordered " + kCstHigh,
       "-include_ordered " + kCstLow + " -include_ordered " + kCstHigh, 5},
      {"ordered reversed", "--include-ordered " + kCstHigh + " --include-ordered " + kCstLow,
       "-include_ordered " + kCstHigh + " -include_ordered " + kCstLow, 5},
      {"ends only", "--include " + kCstHigh + " --ends-only", "-include " + kCstHigh + " -ends_only", 3},
      {"mask on another grid", "--include " + m, "-include " + m, 10},
      {"mask excluded", "--include " + kCc + " --exclude " + m, "-include " + kCc + " -exclude " + m, 1},
      {"label of an atlas", "--include " + q(dir / "labels.nii.gz") + ":7",
       "-include " + q(dir / "label7.nii.gz"), 20},
  };
  std::size_t ordered = 0, reversed = 0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const fs::path a = dir / ("ours" + std::to_string(c) + ".tck"), b = dir / ("tckedit" + std::to_string(c) + ".tck");
    const auto r = runDtfabric("select " + q(tracks) + " -o " + q(a) + " " + cases[c].ours, dir);
    ASSERT_EQ(r.exitCode, 0) << cases[c].name << "\n" << r.err;
    ASSERT_EQ(runTckedit(tracks, b, cases[c].theirs), 0) << cases[c].name;
    expectSameLines(a, b, cases[c].name);
    const std::size_t n = dtf::io::readTck(a.string()).lineCount();
    EXPECT_GE(n, cases[c].atLeast) << cases[c].name;
    EXPECT_LT(n, 2000u) << cases[c].name << " selected everything";
    if (cases[c].name == "ordered") ordered = n;
    if (cases[c].name == "ordered reversed") reversed = n;
  }
  // The tracks were seeded everywhere, so the bundle is walked both ways: the orders split it.
  EXPECT_GT(ordered, 0u);
  EXPECT_GT(reversed, 0u);
}

TEST(SelectCli, BoxesKeepTheStreamlinesWithAVertexInside) {
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = dtf::test::scratchDir();
  const auto r = runDtfabric("select " + q(tracks) + " -o " + q(dir / "box.tck") + " --include box:10,-5,15,26,10,30",
                             dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const dtf::Polylines all = dtf::io::readTck(tracks.string()), kept = dtf::io::readTck((dir / "box.tck").string());
  std::size_t expected = 0;
  for (std::size_t l = 0; l < all.lineCount(); ++l) {
    bool in = false;
    for (std::uint32_t p = all.offsets[l]; p < all.offsets[l + 1] && !in; ++p) {
      const glm::vec3 v = all.points[p];
      in = v.x >= 10 && v.x <= 26 && v.y >= -5 && v.y <= 10 && v.z >= 15 && v.z <= 30;
    }
    expected += in;
  }
  EXPECT_GT(expected, 20u);
  EXPECT_EQ(kept.lineCount(), expected);
}

TEST(SelectCli, RegionSetFileGivesTheSameSelectionAsTheFlags) {
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = dtf::test::scratchDir();
  {
    std::ofstream f(dir / "cst.json");
    f << R"({"format": "dtfabric-regions", "version": 1, "ends_only": false, "precise": false,
  "regions": [
    {"name": "internal capsule", "kind": "include", "shape": "sphere", "centre": [18, 3.7, 21.6], "radius": 6},
    {"name": "corona radiata", "kind": "include", "shape": "sphere", "centre": [20, 0, 45], "radius": 10, "visible": false},
    {"kind": "exclude", "shape": "box", "min": [-5, -100, -100], "max": [5, 100, 100]}]})";
  }
  auto a = runDtfabric("select " + q(tracks) + " -o " + q(dir / "file.tck") + " --roi " + q(dir / "cst.json"), dir);
  ASSERT_EQ(a.exitCode, 0) << a.err;
  auto b = runDtfabric("select " + q(tracks) + " -o " + q(dir / "flags.tck") + " --include " + kCstLow +
                           " --include " + kCstHigh + " --exclude box:-5,-100,-100,5,100,100",
                       dir);
  ASSERT_EQ(b.exitCode, 0) << b.err;
  expectSameLines(dir / "file.tck", dir / "flags.tck", "region set file");
  EXPECT_GT(dtf::io::readTck((dir / "file.tck").string()).lineCount(), 20u);
  // Flags add to the file's regions.
  auto c = runDtfabric("select " + q(tracks) + " -o " + q(dir / "both.tck") + " --roi " + q(dir / "cst.json") +
                           " --ends-only --json",
                       dir);
  ASSERT_EQ(c.exitCode, 0) << c.err;
  EXPECT_EQ(dtf::test::jsonNumber(c.out, "regions"), 3);
  EXPECT_NE(c.out.find("\"ends_only\": true"), std::string::npos) << c.out;
}

TEST(SelectCli, PreciseKeepsASupersetAndLengthsBound) {
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = dtf::test::scratchDir();
  // A slab 0.2 mm thick across x = 18 mm: most streamlines that cross it step over it between two vertices
  // 1 mm apart, and only --precise sees those.
  const std::string slab = " --include box:17.9,-200,-200,18.1,200,200 --json";
  auto a = runDtfabric("select " + q(tracks) + " -o " + q(dir / "v.tck") + slab, dir);
  auto b = runDtfabric("select " + q(tracks) + " -o " + q(dir / "p.tck") + slab + " --precise", dir);
  ASSERT_EQ(a.exitCode, 0) << a.err;
  ASSERT_EQ(b.exitCode, 0) << b.err;
  EXPECT_GT(dtf::test::jsonNumber(b.out, "selected"), 1.5 * dtf::test::jsonNumber(a.out, "selected"));
  // Every streamline with a vertex in the slab is among the precise ones; the precise ones cross x = 18.
  const dtf::Polylines v = dtf::io::readTck((dir / "v.tck").string()), p = dtf::io::readTck((dir / "p.tck").string());
  std::size_t crossing = 0;
  for (std::size_t i = 0; i < p.lineCount(); ++i) {
    float lo = 1e9f, hi = -1e9f;
    for (std::uint32_t k = p.offsets[i]; k < p.offsets[i + 1]; ++k) {
      lo = std::min(lo, p.points[k].x);
      hi = std::max(hi, p.points[k].x);
    }
    crossing += lo <= 18.1f && hi >= 17.9f;
  }
  EXPECT_EQ(crossing, p.lineCount());
  EXPECT_GE(p.lineCount(), v.lineCount());
  auto c = runDtfabric("select " + q(tracks) + " -o " + q(dir / "l.tck") + " --min-length 100 --max-length 150", dir);
  ASSERT_EQ(c.exitCode, 0) << c.err;
  const dtf::Polylines l = dtf::io::readTck((dir / "l.tck").string());
  ASSERT_GT(l.lineCount(), 10u);
  for (std::size_t i = 0; i < l.lineCount(); ++i) {
    double len = 0;
    for (std::uint32_t p = l.offsets[i] + 1; p < l.offsets[i + 1]; ++p)
      len += glm::length(glm::dvec3(l.points[p]) - glm::dvec3(l.points[p - 1]));
    EXPECT_GE(len, 100 - 1e-3);
    EXPECT_LE(len, 150 + 1e-3);
  }
}

TEST(SelectCli, TrxGroupsAndValuesAreKeptAndAsGroupAddsOne) {
  DTF_SHARED_FILE(afq, "niivue_tracts/afq_tractography.trx");
  DTF_SHARED_FILE(dpsv, "niivue_tracts/dpsv.trx");
  const fs::path dir = dtf::test::scratchDir();
  const dtf::Polylines all = dtf::io::readTrx(afq.string());
  // A box over the left half keeps ARC_L's streamlines and few of ARC_R's.
  auto r = runDtfabric("select " + q(afq) + " -o " + q(dir / "left.trx") + " --include box:-200,-200,-200,-5,200,200",
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const dtf::Polylines left = dtf::io::readTrx((dir / "left.trx").string());
  ASSERT_EQ(left.groups.size(), all.groups.size());
  ASSERT_GT(left.lineCount(), 0u);
  EXPECT_LT(left.lineCount(), all.lineCount());
  for (const auto& g : left.groups)
    for (std::uint32_t i : g.lines)
      EXPECT_LT(i, left.lineCount()) << g.name;
  // --as-group: every streamline, the selection as a new group.
  r = runDtfabric("select " + q(afq) + " -o " + q(dir / "grouped.trx") +
                      " --include box:-200,-200,-200,-5,200,200 --as-group left_half",
                  dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const dtf::Polylines grouped = dtf::io::readTrx((dir / "grouped.trx").string());
  EXPECT_EQ(grouped.lineCount(), all.lineCount());
  ASSERT_EQ(grouped.groups.size(), all.groups.size() + 1);
  EXPECT_EQ(grouped.groups.back().name, "left_half");
  EXPECT_EQ(grouped.groups.back().lines.size(), left.lineCount());
  // Per-point and per-streamline values follow their streamlines.
  r = runDtfabric("select " + q(dpsv) + " -o " + q(dir / "dpsv.trx") + " --min-length 60", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const dtf::Polylines d = dtf::io::readTrx(dpsv.string()), s = dtf::io::readTrx((dir / "dpsv.trx").string());
  ASSERT_EQ(s.perLine.size(), d.perLine.size());
  ASSERT_EQ(s.perPoint.size(), d.perPoint.size());
  ASSERT_GT(s.lineCount(), 0u);
  EXPECT_EQ(s.perLine[0].values.size(), s.lineCount() * static_cast<std::size_t>(s.perLine[0].components));
  EXPECT_EQ(s.perPoint[0].values.size(), s.points.size() * static_cast<std::size_t>(s.perPoint[0].components));
  EXPECT_TRUE(s.inconsistency().empty()) << s.inconsistency();
}

TEST(SelectCli, SeveralInputsAreConcatenatedAndInputsAreNeverReplaced) {
  DTF_SHARED_FILE(tracks, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(vtk, "iu_prisma_dwi/derived/tracks_det_first500.vtk");
  const fs::path dir = dtf::test::scratchDir();
  auto r = runDtfabric("select " + q(tracks) + " " + q(vtk) + " -o " + q(dir / "both.vtk") + " --include " + kCc +
                           " --json",
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto one = runDtfabric("select " + q(tracks) + " -o " + q(dir / "one.tck") + " --include " + kCc + " --json", dir);
  auto half = runDtfabric("select " + q(vtk) + " -o " + q(dir / "half.tck") + " --include " + kCc + " --json", dir);
  ASSERT_EQ(one.exitCode, 0) << one.err;
  ASSERT_EQ(half.exitCode, 0) << half.err;
  EXPECT_EQ(dtf::test::jsonNumber(r.out, "streamlines"), 2500);
  EXPECT_EQ(dtf::test::jsonNumber(r.out, "selected"),
            dtf::test::jsonNumber(one.out, "selected") + dtf::test::jsonNumber(half.out, "selected"));
  // The output may not be an input, and an existing output needs --force.
  r = runDtfabric("select " + q(dir / "one.tck") + " -o " + q(dir / "one.tck") + " --include " + kCc, dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("one.tck"), std::string::npos) << r.err;
  r = runDtfabric("select " + q(tracks) + " -o " + q(dir / "half.tck") + " --include " + kCc, dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
}

TEST(SelectCli, TargetedTrackingKeepsOnlyStreamlinesThroughTheRegions) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const fs::path dir = dtf::test::scratchDir();
  auto r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "cst.tck") + " --select 40 --include " + kCstLow +
                           " --include " + kCstHigh + " --exclude " + kMidline + " --json",
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(dtf::test::jsonNumber(r.out, "streamlines"), 40);
  EXPECT_GT(dtf::test::jsonNumber(r.out, "rejected_by_regions"), 40);
  // Selecting them again with the same regions keeps every one.
  r = runDtfabric("select " + q(dir / "cst.tck") + " -o " + q(dir / "again.tck") + " --include " + kCstLow +
                      " --include " + kCstHigh + " --exclude " + kMidline + " --json",
                  dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(dtf::test::jsonNumber(r.out, "selected"), 40);
  // The corticospinal tract runs superior-inferior: its streamlines span far more z than x.
  const dtf::Polylines l = dtf::io::readTck((dir / "cst.tck").string());
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const auto& p : l.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  EXPECT_GT(hi.z - lo.z, 2 * (hi.x - lo.x)) << "x " << lo.x << ".." << hi.x << ", z " << lo.z << ".." << hi.z;
}
