// `dtfabric render` end to end: writes a PNG, the same arguments give the same bytes, bad input and
// usage give the documented exit codes (1 usage, 2 bad input).
#include "support/cli.h"
#include "support/gl_test.h"

#include "io/formats/png_io.h"

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

using dtf::test::CliRun;

CliRun dtfabric(const std::string& args) {
  // Not scratchDir(): that empties the test's directory on every call.
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return dtf::test::runDtfabricCombined(
      args, dtf::test::binaryDir() / "test_scratch" / (std::string("render_cli_") + info->name() + ".log"));
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

} // namespace

TEST(RenderCli, WritesTheSamePngTwice) {
  DTF_GL_TEST_SETUP();
  ASSERT_TRUE(fs::exists(kPhantom)) << kPhantom;
  const fs::path dir = dtf::test::scratchDir();
  const fs::path a = dir / "a.png", b = dir / "b.png";
  const std::string common = kPhantom.string() + " --size 160x128 --surface fa=0.25 --view anterior --seed 3";
  CliRun r1 = dtfabric("render " + common + " -o " + a.string());
  ASSERT_EQ(r1.code, 0) << r1.output;
  CliRun r2 = dtfabric("render " + common + " -o " + b.string());
  ASSERT_EQ(r2.code, 0) << r2.output;
  dtf::Image img = dtf::io::readPng(a.string());
  EXPECT_EQ(img.width, 160);
  EXPECT_EQ(img.height, 128);
  std::size_t lit = 0;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4) lit += (img.rgba[i] | img.rgba[i + 1] | img.rgba[i + 2]) != 0;
  EXPECT_GT(lit, img.rgba.size() / 4 / 10); // something was drawn
  EXPECT_EQ(bytes(a), bytes(b));
  // Another seed gives another texture.
  CliRun r3 = dtfabric("render " + kPhantom.string() + " --size 160x128 --surface fa=0.25 --view anterior --seed 4 -o " +
                    (dir / "c.png").string());
  ASSERT_EQ(r3.code, 0) << r3.output;
  EXPECT_NE(bytes(a), bytes(dir / "c.png"));
}

// An FA isosurface lies at one FA, so the anatomy look's FA ramp would make the whole surface equally
// translucent over the grey beneath (0.35 at FA 0.25: a dark figure). There its fabric is opaque: the same
// colours as the plain look on the same surface, and brighter than the ramp would give.
TEST(RenderCli, AnatomyLookOnAnFaIsosurfaceIsOpaque) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const std::string common = kPhantom.string() + " --size 128x128 --surface fa=0.25 --seed 3";
  auto mean = [&](const std::string& look, const std::string& name) {
    const CliRun r = dtfabric("render " + common + " --look " + look + " -o " + (dir / name).string());
    EXPECT_EQ(r.code, 0) << r.output;
    const dtf::Image img = dtf::io::readPng((dir / name).string());
    double sum = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4)
      sum += img.rgba[i] + img.rgba[i + 1] + img.rgba[i + 2];
    return sum / (img.rgba.size() / 4);
  };
  const double anatomy = mean("anatomy", "anatomy.png"), plain = mean("plain", "plain.png");
  EXPECT_NEAR(anatomy, plain, 0.03 * plain);
  // The ramp asked for explicitly on a slice still applies there (the rule is the FA isosurface's only).
  const CliRun slice =
      dtfabric("render " + kPhantom.string() +
               " --size 128x128 --slice axial --seed 3 --opacity-fa-low 0.9 --opacity-fa-high 0.95 -o " +
               (dir / "slice.png").string());
  ASSERT_EQ(slice.code, 0) << slice.output;
  const CliRun slicePlain =
      dtfabric("render " + kPhantom.string() + " --size 128x128 --slice axial --seed 3 --look plain -o " +
               (dir / "slice_plain.png").string());
  ASSERT_EQ(slicePlain.code, 0) << slicePlain.output;
  EXPECT_NE(bytes(dir / "slice.png"), bytes(dir / "slice_plain.png"));
}

TEST(RenderCli, HelpStatesTheViewConventions) {
  CliRun r = dtfabric("render --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("RADIOLOGICAL"), std::string::npos);
  EXPECT_NE(r.output.find("--neurological"), std::string::npos);
}

TEST(RenderCli, BadUsageAndInputGiveTheirExitCodes) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string out = " -o " + (dir / "x.png").string();
  EXPECT_EQ(dtfabric("render " + kPhantom.string()).code, 1);                                // no -o
  EXPECT_EQ(dtfabric("render " + kPhantom.string() + out + " --color purple").code, 1);      // bad option value
  EXPECT_EQ(dtfabric("render " + kPhantom.string() + out + " --view oblique").code, 1);      // bad view
  EXPECT_EQ(dtfabric("render " + kPhantom.string() + out + " --size 0x0").code, 1);
  EXPECT_EQ(dtfabric("render " + kPhantom.string() + out + " --frobnicate 1").code, 1);      // unknown option
  CliRun missing = dtfabric("render " + (dir / "missing.nii.gz").string() + out);
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing.nii.gz"), std::string::npos);
  std::ofstream(dir / "garbage.nii.gz") << "not a nifti file";
  EXPECT_EQ(dtfabric("render " + (dir / "garbage.nii.gz").string() + out).code, 2);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}
