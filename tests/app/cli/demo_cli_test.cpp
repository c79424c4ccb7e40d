// SPDX-License-Identifier: GPL-3.0-or-later
// `.ci/demo` without a display: it fits the bundled real brain and writes its four figures, and they show
// the anatomy they are captioned with.
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/figures.h"
#include "support/test_env.h"

#include <gtest/gtest.h>

namespace fs = std::filesystem;

namespace {

const char* kFigures[] = {"axial_cc.png", "axial_cc_decfa.png", "coronal_cst.png", "fa_left.png",
                           "axial_cc_tracts.png"};

// Runs the demo's headless path with this build's executable (no package check, no build) into `out`.
dtf::test::CliResult runDemo(const fs::path& out, const fs::path& scratch) {
  const fs::path stdoutFile = scratch / "demo_stdout.txt", stderrFile = scratch / "demo_stderr.txt";
  const std::string cmd = "env -u DISPLAY DTFABRIC='" + std::string(DTF_EXE) + "' DTF_DEMO_OUT='" +
                          out.string() + "' DTF_DEMO_SIZE=256 bash '" +
                          (dtf::test::sourceDir() / ".ci" / "demo").string() + "' >'" + stdoutFile.string() +
                          "' 2>'" + stderrFile.string() + "'";
  const int status = std::system(cmd.c_str());
  dtf::test::CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  r.out = dtf::test::readText(stdoutFile);
  r.err = dtf::test::readText(stderrFile);
  return r;
}

} // namespace

TEST(Demo, HeadlessWritesTheRealBrainFiguresAndPrintsTheirPaths) {
  const fs::path scratch = dtf::test::scratchDir(), out = scratch / "demo";
  const auto r = runDemo(out, scratch);
  if (r.exitCode == 3 && !dtf::test::envFlag("DTF_REQUIRE_GL")) GTEST_SKIP() << "no GL: " << r.err;
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("sample_data/dwi.nii.gz"), std::string::npos) << "the demo fits the bundled DWI\n"
                                                                     << r.err;
  for (const char* name : kFigures) {
    const fs::path f = out / name;
    EXPECT_NE(r.out.find(f.string()), std::string::npos) << "path not printed: " << f << "\n" << r.out;
    EXPECT_EQ(dtf::test::figureProblem(f), "");
  }
  EXPECT_TRUE(fs::exists(out / "dti_tensor.nii.gz"));
}

// The captions' anatomy: the body of the corpus callosum in the middle of the axial slice is red with
// left-right threads; the corticospinal tracts in the coronal slice are blue with vertical threads.
TEST(Demo, FiguresShowCorpusCallosumRedAndCorticospinalTractsBlue) {
  const fs::path scratch = dtf::test::scratchDir(), out = scratch / "demo";
  const auto r = runDemo(out, scratch);
  if (r.exitCode == 3 && !dtf::test::envFlag("DTF_REQUIRE_GL")) GTEST_SKIP() << "no GL: " << r.err;
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;

  const dtf::Image axial = dtf::io::readPng((out / "axial_cc.png").string());
  const auto cc = dtf::test::meanColour(axial, 0.44, 0.42, 0.56, 0.56);
  EXPECT_GT(cc.r, 1.5 * cc.g) << "corpus callosum " << cc.r << " " << cc.g << " " << cc.b;
  EXPECT_GT(cc.r, 1.5 * cc.b) << "corpus callosum " << cc.r << " " << cc.g << " " << cc.b;
  EXPECT_LT(dtf::test::horizontalOverVerticalChange(axial, 0.44, 0.42, 0.56, 0.56), 0.8)
      << "threads in the corpus callosum should run left-right";

  const dtf::Image coronal = dtf::io::readPng((out / "coronal_cst.png").string());
  // The right and the left tract (radiological: right on the left). The camera frames the slice's data (the
  // b=0 image beneath reaches beyond it) inside the orientation letters' band.
  for (const double x0 : {0.31, 0.535}) {
    const auto cst = dtf::test::meanColour(coronal, x0, 0.35, x0 + 0.07, 0.55);
    EXPECT_GT(cst.b, 1.3 * cst.r) << "tract at x " << x0 << ": " << cst.r << " " << cst.g << " " << cst.b;
    EXPECT_GT(cst.b, 1.3 * cst.g) << "tract at x " << x0 << ": " << cst.r << " " << cst.g << " " << cst.b;
    EXPECT_GT(dtf::test::horizontalOverVerticalChange(coronal, x0, 0.35, x0 + 0.07, 0.55), 1.25)
        << "threads in the corticospinal tract at x " << x0 << " should run vertically";
  }
}
