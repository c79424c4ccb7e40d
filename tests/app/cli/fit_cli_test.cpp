// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric fit` end to end through the real executable: the IU Prisma DWI fitted and read back, output
// overwrite rules, and bad input (exit 2, file named) or bad usage (exit 1).
#include "io/formats/tensor_io.h"
#include "support/test_env.h"

#include <cstdlib>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <sys/wait.h>

using namespace dtf;

namespace {

namespace fs = std::filesystem;

struct CliResult {
  int code = -1;
  std::string out, err;
};

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs dtfabric with `args`, stdout and stderr captured to files (so stderr is not a terminal).
CliResult dtfabric(const std::vector<std::string>& args) {
  // Beside the test's scratch directory (scratchDir() would empty it), one per test: ctest runs in parallel.
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = dtf::test::binaryDir() / "test_scratch" /
                       (std::string(info->test_suite_name()) + "." + info->name() + ".output");
  fs::create_directories(dir);
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  std::string cmd = quote(DTF_EXE);
  for (const auto& a : args)
    cmd += " " + quote(a);
  cmd += " >" + quote(out.string()) + " 2>" + quote(err.string()) + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

void writeText(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

} // namespace

TEST(FitCli, FitsRealDwiWithSiblingGradientFilesAndMask) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  DTF_SHARED_FILE(mask, "iu_prisma_dwi/derived/mask.nii.gz");
  const fs::path out = dtf::test::scratchDir() / "tensor.nii.gz";
  // No --bval/--bvec: dwi.bval and dwi.bvec beside the DWI are found.
  CliResult r = dtfabric({"fit", dwi.string(), "--mask", mask.string(), "-o", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("fitting: 100%"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << "no carriage returns when stderr is not a terminal";
  EXPECT_NE(r.err.find("fitted 49040 voxels"), std::string::npos) << r.err;
  io::LoadedTensors t = io::readTensorVolume(out.string(), io::TensorLayout::Fsl);
  ASSERT_EQ(t.field.grid.dims, glm::ivec3(72, 72, 39));
  // Corpus callosum voxel in world RAS (README's voxel-frame tensor with xy and xz negated).
  const SymTensor cc = t.field.at(33, 42, 22);
  EXPECT_NEAR(cc.xx, 1.4692e-3, 2e-6);
  EXPECT_NEAR(cc.xy, -1.1027e-4, 2e-6);
  EXPECT_NEAR(cc.xz, 3.7012e-4, 2e-6);
  EXPECT_FALSE(t.field.valid[t.field.grid.index(0, 0, 0)]) << "outside the mask";
}

TEST(FitCli, AutomaticMaskOlsAndMrtrixLayoutOnSmallDwi) {
  DTF_SHARED_FILE(dwi, "dipy_small/small_101D.nii.gz");
  const fs::path out = dtf::test::scratchDir() / "t.nii";
  CliResult r = dtfabric({"fit", dwi.string(), "--method", "ols", "--layout", "mrtrix", "-o", out.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  io::LoadedTensors t = io::readTensorVolume(out.string(), io::TensorLayout::Mrtrix);
  std::size_t valid = 0;
  for (auto v : t.field.valid)
    valid += v;
  EXPECT_GT(valid, 0u);
}

TEST(FitCli, RefusesExistingOutputUnlessForcedAndNeverAnInput) {
  DTF_SHARED_FILE(dwi, "dipy_small/small_64D.nii");
  const fs::path dir = dtf::test::scratchDir();
  // A private copy of the inputs, so a failed refusal could not damage shared data.
  for (const char* ext : {".nii", ".bval", ".bvec"})
    fs::copy_file(dwi.parent_path() / (std::string("small_64D") + ext), dir / (std::string("d") + ext));
  const std::string in = (dir / "d.nii").string(), out = (dir / "t.nii.gz").string();
  ASSERT_EQ(dtfabric({"fit", in, "-o", out}).code, 0);
  CliResult again = dtfabric({"fit", in, "-o", out});
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  EXPECT_EQ(dtfabric({"fit", in, "-o", out, "--force"}).code, 0);
  const auto sizeBefore = fs::file_size(in);
  CliResult self = dtfabric({"fit", in, "-o", in, "--force"});
  EXPECT_EQ(self.code, 2) << self.err;
  EXPECT_EQ(fs::file_size(in), sizeBefore);
}

TEST(FitCli, BadInputExitsTwoNamingTheFile) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  const fs::path dir = dtf::test::scratchDir();
  const std::string bvec = (dwi.parent_path() / "dwi.bvec").string();
  const std::string out = (dir / "t.nii.gz").string();

  const fs::path short_ = dir / "twenty.bval";
  writeText(
      short_,
      "0 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500 2500\n");
  CliResult mismatch = dtfabric({"fit", dwi.string(), "--bval", short_.string(), "--bvec", bvec, "-o", out});
  EXPECT_EQ(mismatch.code, 2);
  EXPECT_NE(mismatch.err.find(short_.string()), std::string::npos) << mismatch.err;
  EXPECT_NE(mismatch.err.find("20 b-values"), std::string::npos) << mismatch.err;
  EXPECT_NE(mismatch.err.find("21 volumes"), std::string::npos) << mismatch.err;
  EXPECT_NE(mismatch.err.find("dwi.nii.gz"), std::string::npos) << mismatch.err;

  const fs::path missing = dir / "missing.bvec";
  CliResult noBvec = dtfabric({"fit", dwi.string(), "--bval", (dwi.parent_path() / "dwi.bval").string(),
                               "--bvec", missing.string(), "-o", out});
  EXPECT_EQ(noBvec.code, 2);
  EXPECT_NE(noBvec.err.find(missing.string()), std::string::npos) << noBvec.err;

  const fs::path text = dir / "text.bval";
  writeText(text, "0 2500 2500\n2500 b2500 2500\n");
  CliResult nonNumeric = dtfabric({"fit", dwi.string(), "--bval", text.string(), "--bvec", bvec, "-o", out});
  EXPECT_EQ(nonNumeric.code, 2);
  EXPECT_NE(nonNumeric.err.find(text.string() + " line 2"), std::string::npos) << nonNumeric.err;
  const fs::path noDwi = dir / "absent.nii.gz";
  CliResult missingDwi =
      dtfabric({"fit", noDwi.string(), "--bval", text.string(), "--bvec", bvec, "-o", out});
  EXPECT_EQ(missingDwi.code, 2);
  EXPECT_NE(missingDwi.err.find(noDwi.string()), std::string::npos) << missingDwi.err;
  EXPECT_FALSE(fs::exists(out)) << "no output after a failure";
}

TEST(FitCli, UsageErrorsExitOneAndHelpExitsZero) {
  CliResult help = dtfabric({"fit", "--help"});
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--b0-threshold"), std::string::npos);
  EXPECT_EQ(dtfabric({"fit"}).code, 1);
  EXPECT_EQ(dtfabric({"fit", "x.nii.gz"}).code, 1) << "missing -o";
  EXPECT_EQ(dtfabric({"fit", "x.nii.gz", "-o", "y.nii.gz", "--method", "lsq"}).code, 1);
  EXPECT_EQ(dtfabric({"fit", "x.nii.gz", "-o", "y.nii.gz", "--layout", "nope"}).code, 1);
  EXPECT_EQ(dtfabric({"fit", "x.nii.gz", "-o", "y.nii.gz", "--bogus", "1"}).code, 1);
  EXPECT_EQ(dtfabric({"fit", "x.nii.gz", "-o", "y.txt"}).code, 1);
}
