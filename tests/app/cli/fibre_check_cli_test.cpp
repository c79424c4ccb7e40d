// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric check` on fibre sets, end to end on the real Prisma peaks: each file in its own layout is ok,
// a file read in the other frame is corrected with the x flip, the JSON keys are those of the tensor check,
// and what a fibre set cannot do (--sheet, --fix-bvec) is refused as usage.
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>
#include <regex>

namespace {

namespace fs = std::filesystem;
using dtf::test::runDtfabric;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

std::string jsonText(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": \"([^\"]*)\""))) return "";
  return m[1];
}

std::string correctionText(const std::string& json) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"correction\": (\\[\\[[^\\n]*?\\]\\])"))) return "";
  return m[1];
}

class FibreCheckCli : public ::testing::Test {
protected:
  void SetUp() override {
    DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
    fibres_ = mrtrix.parent_path();
    tensor_ = fibres_.parent_path() / "dti_tensor.nii.gz";
    scratch_ = dtf::test::scratchDir();
  }
  dtf::test::CliResult check(const std::string& args) const {
    return runDtfabric("check " + args + " --json", scratch_);
  }
  fs::path fibres_, tensor_, scratch_;
};

TEST_F(FibreCheckCli, EachFileInItsOwnLayoutIsOkWithTheTensorJsonKeys) {
  struct Case {
    std::string args, layout, frame;
  };
  for (const Case& c : {Case{q(fibres_ / "peaks_mrtrix.nii.gz"), "mrtrix-peaks", "world"},
                        Case{q(fibres_ / "peaks_dipy.nii.gz"), "dipy-peaks", "voxel"},
                        Case{q(fibres_ / "bedpostx_layout"), "bedpostx", "fsl"}}) {
    for (const std::string& extra : {std::string(), " --tensor " + q(tensor_)}) {
      const auto r = check(c.args + extra);
      ASSERT_EQ(r.exitCode, 0) << c.args << extra << ": " << r.err;
      EXPECT_EQ(jsonText(r.out, "verdict"), "ok") << c.args << extra << "\n" << r.out;
      EXPECT_EQ(jsonText(r.out, "kind"), "fibres");
      EXPECT_EQ(jsonText(r.out, "frame"), c.frame) << c.args;
      EXPECT_EQ(jsonText(r.out, "correction_name"), "x y z");
      EXPECT_GT(dtf::test::jsonNumber(r.out, "margin"), 0.08) << c.args << extra;
      EXPECT_NE(r.out.find(c.layout + " layout"), std::string::npos) << r.out;
      for (const char* key :
           {"input", "kind", "frame", "verdict", "reason", "correction", "correction_name", "score_given",
            "score_best", "margin", "best", "runner_up", "mask_voxels", "white_matter_voxels",
            "white_matter_rule", "thresholds", "seconds", "candidates"})
        EXPECT_NE(r.out.find("\"" + std::string(key) + "\":"), std::string::npos) << key;
      EXPECT_EQ(
          jsonText(r.out, "white_matter_rule").rfind(extra.empty() ? "single dominant" : "FA >= 0.30", 0), 0u)
          << jsonText(r.out, "white_matter_rule");
    }
  }
}

TEST_F(FibreCheckCli, AFileReadInTheOtherFrameIsCorrectedWithTheXFlip) {
  for (const std::string& args : {q(fibres_ / "peaks_dipy.nii.gz") + " --layout mrtrix-peaks",
                                  q(fibres_ / "peaks_mrtrix.nii.gz") + " --layout dipy-peaks"}) {
    for (const std::string& extra : {std::string(), " --tensor " + q(tensor_)}) {
      const auto r = check(args + extra);
      ASSERT_EQ(r.exitCode, 0) << args << extra << ": " << r.err;
      EXPECT_EQ(jsonText(r.out, "verdict"), "corrected") << args << extra << "\n" << r.out;
      EXPECT_EQ(correctionText(r.out), "[[-1, 0, 0], [0, 1, 0], [0, 0, 1]]") << args << extra;
      EXPECT_EQ(jsonText(r.out, "correction_name"), "-x y z");
      EXPECT_LT(dtf::test::jsonNumber(r.out, "score_given"),
                0.85 * dtf::test::jsonNumber(r.out, "score_best"));
    }
  }
  // The text form names the stored frame and the verdict.
  const auto t =
      runDtfabric("check " + q(fibres_ / "peaks_dipy.nii.gz") + " --layout mrtrix-peaks", scratch_);
  ASSERT_EQ(t.exitCode, 0) << t.err;
  EXPECT_NE(t.out.find("candidates act on the world frame"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("verdict: corrected"), std::string::npos) << t.out;
}

TEST_F(FibreCheckCli, SheetFixBvecAndBadTensorAreRefused) {
  const std::string peaks = q(fibres_ / "peaks_mrtrix.nii.gz");
  auto r = runDtfabric("check " + peaks + " --sheet " + q(scratch_ / "s.png"), scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_NE(r.err.find("fibre set"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "s.png"));
  r = runDtfabric("check " + peaks + " --fix-bvec " + q(scratch_ / "f.bvec"), scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_FALSE(fs::exists(scratch_ / "f.bvec"));
  // A missing tensor: exit 2 naming the file.
  const fs::path missing = scratch_ / "no_such_tensor.nii.gz";
  r = runDtfabric("check " + peaks + " --tensor " + q(missing), scratch_);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("no_such_tensor"), std::string::npos) << r.err;
  // --tensor with a tensor-file INPUT is a usage error.
  r = runDtfabric("check " + q(fibres_.parent_path() / "dti_tensor.nii.gz") + " --tensor " + q(tensor_),
                  scratch_);
  EXPECT_EQ(r.exitCode, 1) << r.err;
}

} // namespace
