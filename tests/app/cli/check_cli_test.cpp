// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric check` end to end on the real data: the JSON keys, corrupted tables corrected back through
// --fix-bvec, tensor files in the wrong layout, the DIPY crops, and bad input (exit 2 naming the file).
#include "io/diffusion/dwi.h"
#include "io/formats/tensor_io.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <fstream>
#include <gtest/gtest.h>
#include <regex>

namespace {

namespace fs = std::filesystem;
using dtf::test::runDtfabric;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// Writes an FSL 3-row table, row r of column n = f(r, n).
template <typename F> void writeTable(const fs::path& path, std::size_t n, F f) {
  std::ofstream os(path);
  for (int r = 0; r < 3; ++r) {
    for (std::size_t i = 0; i < n; ++i)
      os << (i ? " " : "") << f(r, i);
    os << "\n";
  }
}

std::string jsonText(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": \"([^\"]*)\""))) return "";
  return m[1];
}

// The "correction" member as 9 integers, row-major.
std::vector<int> correction(const std::string& json) {
  std::smatch m;
  std::vector<int> out;
  if (!std::regex_search(json, m, std::regex("\"correction\": (\\[\\[[^\\n]*?\\]\\])"))) return out;
  const std::string s = m[1];
  std::regex num("-?[0-9]+");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), num); it != std::sregex_iterator(); ++it)
    out.push_back(std::stoi(it->str()));
  return out;
}

class CheckCli : public ::testing::Test {
protected:
  void SetUp() override {
    DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
    dir_ = dwi.parent_path();
    scratch_ = dtf::test::scratchDir();
    bvecs_ = dtf::io::readBvecs((dir_ / "dwi.bvec").string());
  }
  std::string dwiArgs(const fs::path& bvec) const {
    return q(dir_ / "dwi.nii.gz") + " --bval " + q(dir_ / "dwi.bval") + " --bvec " + q(bvec) + " --mask " +
           q(dir_ / "derived/mask.nii.gz");
  }
  fs::path dir_, scratch_;
  std::vector<glm::dvec3> bvecs_;
};

TEST_F(CheckCli, TrueTableIsOkWithEveryJsonKey) {
  const auto r = runDtfabric("check " + dwiArgs(dir_ / "dwi.bvec") + " --json", scratch_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonText(r.out, "verdict"), "ok");
  EXPECT_EQ(correction(r.out), (std::vector<int>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  for (const char* key : {"score_given", "score_best", "margin", "mask_voxels", "white_matter_voxels"})
    EXPECT_GE(dtf::test::jsonNumber(r.out, key), 0) << key;
  EXPECT_EQ(dtf::test::jsonNumber(r.out, "mask_voxels"), 49040); // the README's mask size
  EXPECT_DOUBLE_EQ(dtf::test::jsonNumber(r.out, "score_given"), dtf::test::jsonNumber(r.out, "score_best"));
  EXPECT_GT(dtf::test::jsonNumber(r.out, "margin"), 0.1);
  // 24 candidates, each with a matrix and a score.
  std::regex cand("\\{\"name\": \"[^\"]+\", \"matrix\": \\[\\[[-0-9, \\[\\]]+\\]\\], \"score\": [0-9.]+");
  EXPECT_EQ(std::distance(std::sregex_iterator(r.out.begin(), r.out.end(), cand), std::sregex_iterator()),
            24);
  // The text form prints the thresholds.
  const auto t = runDtfabric("check " + dwiArgs(dir_ / "dwi.bvec"), scratch_);
  EXPECT_NE(t.out.find("thresholds: inconclusive below 3000 white-matter voxels or a margin below 7.0%"),
            std::string::npos)
      << t.out;
  EXPECT_NE(t.out.find("verdict: ok"), std::string::npos);
}

// Corrupted tables: detected, and --fix-bvec writes the original table back (up to whole-vector sign).
TEST_F(CheckCli, CorruptedTablesAreFixedBack) {
  struct Case {
    const char* name;
    int perm[3];
    int sign[3]; // row r of the corrupted table = sign[r] * original row perm[r]
  };
  const Case cases[] = {{"flipy", {0, 1, 2}, {1, -1, 1}},
                        {"swapxz", {2, 1, 0}, {1, 1, 1}},
                        {"cycle_flipz", {1, 2, 0}, {1, 1, -1}}};
  for (const Case& c : cases) {
    const fs::path bad = scratch_ / (std::string(c.name) + ".bvec");
    writeTable(bad, bvecs_.size(), [&](int r, std::size_t n) { return c.sign[r] * bvecs_[n][c.perm[r]]; });
    const fs::path fixed = scratch_ / (std::string(c.name) + "_fixed.bvec");
    const auto r = runDtfabric("check " + dwiArgs(bad) + " --json --fix-bvec " + q(fixed), scratch_);
    ASSERT_EQ(r.exitCode, 0) << c.name << ": " << r.err;
    EXPECT_EQ(jsonText(r.out, "verdict"), "corrected") << c.name;
    const auto back = dtf::io::readBvecs(fixed.string());
    ASSERT_EQ(back.size(), bvecs_.size());
    int sign = 0;
    for (std::size_t n = 0; n < back.size(); ++n) {
      if (glm::length(bvecs_[n]) < 0.5) continue;
      const double d = glm::dot(back[n], bvecs_[n]);
      if (sign == 0) sign = d > 0 ? 1 : -1;
      EXPECT_LT(glm::length(back[n] - double(sign) * bvecs_[n]), 1e-6) << c.name << " volume " << n;
    }
    // The fixed table checks ok.
    const auto again = runDtfabric("check " + dwiArgs(fixed) + " --json", scratch_);
    EXPECT_EQ(jsonText(again.out, "verdict"), "ok") << c.name;
  }
}

TEST_F(CheckCli, FixBvecNeverOverwritesAnInputAndRefusesWhenInconclusive) {
  const fs::path copy = scratch_ / "given.bvec";
  fs::copy_file(dir_ / "dwi.bvec", copy);
  const std::string before = dtf::test::readText(copy);
  auto r = runDtfabric("check " + dwiArgs(copy) + " --fix-bvec " + q(copy) + " --force", scratch_);
  EXPECT_NE(r.exitCode, 0);
  EXPECT_EQ(dtf::test::readText(copy), before);

  DTF_SHARED_FILE(crop, "dipy_small/small_64D.nii");
  const fs::path out = scratch_ / "crop_fixed.bvec";
  r = runDtfabric("check " + q(crop) + " --fix-bvec " + q(out), scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("inconclusive"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  r = runDtfabric("check " + q(crop) + " --fix-bvec " + q(out) + " --force", scratch_);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
}

TEST(CheckCliData, DipyCropsAreNeverCorrected) {
  DTF_SHARED_FILE(dir, "dipy_small/small_64D.nii");
  const auto scratch = dtf::test::scratchDir();
  for (const char* name : {"small_64D.nii", "small_101D.nii.gz"}) {
    const auto r = runDtfabric("check " + q(dir.parent_path() / name) + " --json", scratch);
    ASSERT_EQ(r.exitCode, 0) << name << ": " << r.err;
    const std::string v = jsonText(r.out, "verdict");
    EXPECT_TRUE(v == "ok" || v == "inconclusive") << name << ": " << v;
  }
}

TEST(CheckCliData, TensorFilesInTheWrongLayoutOrFrameAreFlagged) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/dti_tensor_mrtrix.nii.gz");
  const auto scratch = dtf::test::scratchDir();
  auto r = runDtfabric("check " + q(fsl) + " --json", scratch);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonText(r.out, "verdict"), "ok");
  EXPECT_EQ(jsonText(r.out, "frame"), "world");
  r = runDtfabric("check " + q(fsl) + " --layout mrtrix --json", scratch);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(jsonText(r.out, "verdict"), "ok");
  // The MRtrix file with its x row negated (xy and xz), written as MRtrix again.
  auto loaded = dtf::io::readTensorVolume(mrtrix.string());
  for (auto& t : loaded.field.tensors) {
    t.xy = -t.xy;
    t.xz = -t.xz;
  }
  const fs::path negated = scratch / "mrtrix_negx.nii.gz";
  dtf::io::writeTensorVolume(negated.string(), loaded.field, dtf::io::TensorLayout::Mrtrix);
  r = runDtfabric("check " + q(negated) + " --layout mrtrix --json", scratch);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonText(r.out, "verdict"), "corrected");
  EXPECT_EQ(correction(r.out), (std::vector<int>{-1, 0, 0, 0, 1, 0, 0, 0, 1}));
}

TEST_F(CheckCli, BadInputExitsTwoNamingTheFileAndTheReason) {
  const std::string dwi = q(dir_ / "dwi.nii.gz");
  // bvec with one direction fewer than the bval.
  const fs::path shortVec = scratch_ / "short.bvec";
  writeTable(shortVec, bvecs_.size() - 1, [&](int r, std::size_t n) { return bvecs_[n][r]; });
  auto r =
      runDtfabric("check " + dwi + " --bval " + q(dir_ / "dwi.bval") + " --bvec " + q(shortVec), scratch_);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("short.bvec"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("directions"), std::string::npos) << r.err;
  // Directions of length 2.
  const fs::path longVec = scratch_ / "long.bvec";
  writeTable(longVec, bvecs_.size(), [&](int r, std::size_t n) { return 2 * bvecs_[n][r]; });
  r = runDtfabric("check " + dwi + " --bval " + q(dir_ / "dwi.bval") + " --bvec " + q(longVec), scratch_);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("long.bvec"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a unit vector"), std::string::npos) << r.err;
  // Every volume b=0.
  const fs::path zeros = scratch_ / "zeros.bval";
  {
    std::ofstream os(zeros);
    for (std::size_t n = 0; n < bvecs_.size(); ++n)
      os << (n ? " " : "") << 0;
    os << "\n";
  }
  r = runDtfabric("check " + dwi + " --bval " + q(zeros) + " --bvec " + q(dir_ / "dwi.bvec"), scratch_);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("zeros.bval"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("every volume is b=0"), std::string::npos) << r.err;
  // A mask on another grid (the other brain's FA map).
  DTF_SHARED_FILE(otherMask, "niivue_fsl_dtifit/FA.nii.gz");
  r = runDtfabric("check " + dwi + " --mask " + q(otherMask), scratch_);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("FA.nii.gz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("another grid"), std::string::npos) << r.err;
}

} // namespace

namespace {

// `bench check` without MRtrix on the PATH: it still times the check and says the peer is absent.
TEST(CheckCliData, BenchReportsAnAbsentPeer) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  const auto scratch = dtf::test::scratchDir();
  // PATH without dwigradcheck: the command runs through a shell with PATH replaced.
  const std::string cmd = "env PATH=" + scratch.string() + " '" + std::string(DTF_EXE) +
                          "' bench check --repeat 1 --json --data " + q(dwi.parent_path().parent_path()) +
                          " >" + q(scratch / "bench.json") + " 2>" + q(scratch / "bench.err");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << dtf::test::readText(scratch / "bench.err");
  const std::string json = dtf::test::readText(scratch / "bench.json");
  EXPECT_NE(json.find("\"peer_ran\": false"), std::string::npos) << json;
  EXPECT_NE(json.find("dwigradcheck is not on the PATH"), std::string::npos) << json;
  EXPECT_EQ(jsonText(json, "verdict"), "ok");
  EXPECT_GT(dtf::test::jsonNumber(json, "seconds"), 0);
}

} // namespace
