// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric track`, `dtfabric compare` and `dtfabric bench tracts` end to end: real brain and phantom input,
// thread-count independent output files, and bad input mapped to exit codes 1 (usage) and 2 (bad input).
#include "support/cli.h"
#include "support/test_env.h"

#include <regex>

using dtf::test::jsonNumber;
using dtf::test::runDtfabric;

namespace {
std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}
} // namespace

TEST(TractCli, TrackWritesTheSameFileForAnyThreadCount) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(mask, "iu_prisma_dwi/derived/mask.nii.gz");
  auto dir = dtf::test::scratchDir();
  const std::string common = "track " + q(tensor) + " --seeds-mask " + q(mask) + " --mask " + q(mask) +
                             " --select 300 --seed 7 --json";
  auto r1 = runDtfabric(common + " --threads 1 -o " + q(dir / "t1.tck"), dir);
  ASSERT_EQ(r1.exitCode, 0) << r1.err;
  auto r2 = runDtfabric(common + " --threads 3 -o " + q(dir / "t3.tck"), dir);
  ASSERT_EQ(r2.exitCode, 0) << r2.err;
  EXPECT_EQ(jsonNumber(r1.out, "streamlines"), 300);
  // Lengths are summed in single precision and reported unrounded: a float's resolution near 30 mm is 2e-6.
  EXPECT_GE(jsonNumber(r1.out, "length_min_mm"), 30 - 1e-4);
  EXPECT_LE(jsonNumber(r1.out, "length_max_mm"), 250 + 1e-4);
  EXPECT_EQ(jsonNumber(r1.out, "points"), jsonNumber(r2.out, "points"));
  const std::string a = dtf::test::readText(dir / "t1.tck"), b = dtf::test::readText(dir / "t3.tck");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_TRUE(a == b) << "output differs between 1 and 3 threads";
  // Existing output without --force is refused.
  auto again = runDtfabric(common + " -o " + q(dir / "t1.tck"), dir);
  EXPECT_EQ(again.exitCode, 2);
  EXPECT_NE(again.err.find("exists"), std::string::npos) << again.err;
}

TEST(TractCli, TrackOtherSeedsAndFormatsOnAPhantom) {
  auto dir = dtf::test::scratchDir();
  auto ph = runDtfabric("phantom brain --size 48 -o " + q(dir / "brain.nii.gz"), dir);
  ASSERT_EQ(ph.exitCode, 0) << ph.err;
  const std::string in = q(dir / "brain.nii.gz");
  auto r = runDtfabric("track " + in + " --seed-slice axial:24 --seeds 400 --min-length 10 --step 0.5 -o " +
                           q(dir / "s.trk"),
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("wrote "), std::string::npos) << r.out;
  r = runDtfabric("track " + in +
                      " --seed-surface slice=coronal:24 --select 50 --min-length 10 --euler --json -o " +
                      q(dir / "s.vtk"),
                  dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(r.out, "streamlines"), 50);
  EXPECT_NE(r.out.find("\"integrator\": \"euler\""), std::string::npos);
  r = runDtfabric(
      "track " + in + " --seed-sphere 0,0,0,6 --select 20 --min-length 5 --json -o " + q(dir / "s.tck"), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // The tracts read back through compare (every format).
  for (const char* f : {"s.trk", "s.vtk", "s.tck"}) {
    auto c = runDtfabric("compare " + in + " --tracts " + q(dir / f) + " --surface slice=axial --json", dir);
    ASSERT_EQ(c.exitCode, 0) << f << ": " << c.err;
    EXPECT_GT(jsonNumber(c.out, "streamlines"), 0) << c.out;
  }
}

// The real MRtrix tracks against the fabric on the real tensors: on an axial slice through the corpus
// callosum most tract points run within 15 degrees of the fabric direction.
TEST(TractCli, CompareRealTracksWithTheFabric) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  auto dir = dtf::test::scratchDir();
  auto r =
      runDtfabric("compare " + q(tensor) + " --tracts " + q(tck) + " --surface slice=axial:22 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_GT(jsonNumber(r.out, "points"), 5000) << r.out;
  EXPECT_LT(jsonNumber(r.out, "median_deg"), 10) << r.out;
  EXPECT_GT(jsonNumber(r.out, "frac_below_15"), 0.7) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "bin_deg"), 10);
  EXPECT_NE(r.out.find("\"histogram\": ["), std::string::npos);
  r = runDtfabric(
      "compare " + q(tensor) + " --tracts " + q(tck) + " --surface slice=axial:22 --bins 6 --near 1", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("median"), std::string::npos);
  EXPECT_NE(r.out.find("75.0- 90.0 deg"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("#"), std::string::npos) << r.out;
}

TEST(TractCli, BadTractFilesAndUsage) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  {
    std::ofstream bad(dir / "bad.tck");
    bad << "mrtrix tracks\ndatatype: Float32LE\nfile: . 999\nEND\n";
  }
  {
    std::ofstream bad(dir / "bad.trk");
    bad << "TRACK";
  }
  for (const char* f : {"bad.tck", "bad.trk", "missing.vtk"}) {
    auto r = runDtfabric("compare " + q(tensor) + " --tracts " + q(dir / f) + " --surface slice=axial", dir);
    EXPECT_EQ(r.exitCode, 2) << f;
    EXPECT_NE(r.err.find((dir / f).string()), std::string::npos) << r.err;
  }
  auto r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "x.tck") + " --select 10 --seeds 10", dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "x.txt"), dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  // Counts beyond what memory and time allow are refused before tracking starts.
  for (const std::string count : {"--select 2e9", "--select 10000001", "--seeds 100000001"}) {
    r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "x.tck") + " " + count, dir);
    EXPECT_EQ(r.exitCode, 1) << count << "\n" << r.err;
    EXPECT_NE(r.err.find("must be (0, 1"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.tck"));
  }
  r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "x.tck") + " --angle 0", dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = runDtfabric("track " + q(tensor) + " -o " + q(dir / "x.tck") + " --seed-sphere 1,2", dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = runDtfabric(
      "track " + q(tensor) + " -o " + q(dir / "x.tck") + " --seed-sphere 500,500,500,2 --select 5", dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("no streamline"), std::string::npos) << r.err;
  r = runDtfabric("compare " + q(tensor) + " --surface slice=axial", dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = runDtfabric("track --help", dir);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("--seeds-mask"), std::string::npos);
  r = runDtfabric("compare --help", dir);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("--near"), std::string::npos);
}

TEST(TractCli, BenchTractsRunsSmall) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  auto dir = dtf::test::scratchDir();
  auto r = runDtfabric("bench tracts --count 500 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(r.out, "streamlines"), 500);
  EXPECT_GT(jsonNumber(r.out, "streamlines_per_s"), 0);
  // The peer runs in the same invocation exactly when MRtrix's tckgen is on the PATH.
  const bool haveTckgen = std::system("command -v tckgen >/dev/null 2>&1") == 0;
  EXPECT_NE(r.out.find(haveTckgen ? "\"peer_ran\": true" : "\"peer_ran\": false"), std::string::npos) << r.out;
  if (haveTckgen) {
    EXPECT_GT(jsonNumber(r.out, "peer_seconds"), 0);
  }
}
