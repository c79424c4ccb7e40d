// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric render` end to end: writes a PNG, the same arguments give the same bytes, bad input and
// usage give the documented exit codes (1 usage, 2 bad input).
#include "io/formats/png_io.h"
#include "render/figure_furniture.h"
#include "support/cli.h"
#include "support/gl_test.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <utility>
#include <vector>

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

// A slice is framed on its data: over the whole grid (a background beneath) as when clipped to the data, so
// the fabric and the DEC-FA look of one slice frame alike (they differed by 15 %). The data stays inside the
// band the orientation letters take at each edge.
TEST(RenderCli, SlicesAreFramedOnTheirDataInsideTheLetters) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const std::string dwi = (dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz").string();
  const std::string common = "render " + dwi + " --slice axial --size 256x256 --look dec-fa";
  const CliRun clipped = dtfabric(common + " -o " + (dir / "clipped.png").string());
  ASSERT_EQ(clipped.code, 0) << clipped.output;
  const CliRun whole = dtfabric(common + " --background fa -o " + (dir / "whole.png").string());
  ASSERT_EQ(whole.code, 0) << whole.output;
  ASSERT_NE(whole.output.find("10082 triangles"), std::string::npos) << "not the whole grid:\n"
                                                                     << whole.output;
  const dtf::Image a = dtf::io::readPng((dir / "clipped.png").string());
  const dtf::Image b = dtf::io::readPng((dir / "whole.png").string());
  double diff = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i)
    diff += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
  EXPECT_LT(diff / a.rgba.size(), 2.0) << "the two framings differ";
  // The DEC colours' extent (chroma above 0.15; letters and scale bar are white, the RGB legend in the corner
  // is left out) lies inside the letters' band.
  int x0 = a.width, x1 = -1, y0 = a.height, y1 = -1;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (x > a.width * 3 / 4 && y > a.height * 3 / 4) continue;
      const std::uint8_t* p = a.pixel(x, y);
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) < 38) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  const int band = dtf::render::letterBand(256, 256);
  EXPECT_GE(std::min({x0, y0, a.width - 1 - x1, a.height - 1 - y1}), band - 2)
      << "data at x " << x0 << ".." << x1 << ", y " << y0 << ".." << y1 << "; band " << band;
  EXPECT_LT(std::min(x0, a.height - 1 - y1), band + 12) << "the data does not fill the frame";
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
  // The limit the help states (8192) is the one applied, and the message says it.
  for (const std::string size : {"9000x100", "99999x10"}) {
    const CliRun big = dtfabric("render " + kPhantom.string() + out + " --size " + size);
    EXPECT_EQ(big.code, 1) << big.output;
    EXPECT_NE(big.output.find("--size must lie between 16x16 and 8192x8192, got " + size), std::string::npos)
        << big.output;
  }
  EXPECT_EQ(dtfabric("render " + kPhantom.string() + out + " --frobnicate 1").code, 1);      // unknown option
  CliRun missing = dtfabric("render " + (dir / "missing.nii.gz").string() + out);
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing.nii.gz"), std::string::npos);
  std::ofstream(dir / "garbage.nii.gz") << "not a nifti file";
  EXPECT_EQ(dtfabric("render " + (dir / "garbage.nii.gz").string() + out).code, 2);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// --fabric-along TRACTS[:MM]: a missing or empty tract file and a bad distance are bad input (exit 2) named
// in the message, before anything is written; a good one renders (the pixels are tested in
// tests/render/anatomy_look_gl_test.cpp).
TEST(RenderCli, FabricAlongRefusesMissingTractsAndBadDistances) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const fs::path png = dir / "x.png", tck = dir / "line.tck";
  // .tck files (MRtrix: a text header, then float32 triplets from byte 64, NaN ends a line, Inf the data):
  // two points across the phantom's centre, and none.
  const auto writeTck = [](const fs::path& path, std::vector<float> pts, int count) {
    std::ofstream f(path, std::ios::binary);
    std::string header =
        "mrtrix tracks\ndatatype: Float32LE\ncount: " + std::to_string(count) + "\nfile: . 64\nEND\n";
    header.resize(64, '\0');
    f << header;
    pts.insert(pts.end(), {INFINITY, INFINITY, INFINITY});
    f.write(reinterpret_cast<const char*>(pts.data()),
            static_cast<std::streamsize>(pts.size() * sizeof(float)));
  };
  writeTck(tck, {-20.0f, 0.0f, 0.0f, 20.0f, 0.0f, 0.0f, NAN, NAN, NAN}, 1);
  writeTck(dir / "empty.tck", {}, 0);
  const std::string base =
      "render " + kPhantom.string() + " -o " + png.string() + " --size 64x64 --fabric-along ";
  for (const auto& [arg, says] : std::vector<std::pair<std::string, std::string>>{
           {(dir / "missing.tck").string(), "missing.tck"},
           {tck.string() + ":abc", "'abc' must be a number of mm"},
           {tck.string() + ":0", "'0' must be a number of mm"},
           {tck.string() + ":", "'' must be a number of mm"},
           {(dir / "empty.tck").string(), "no streamline point"}}) {
    const CliRun r = dtfabric(base + arg);
    EXPECT_EQ(r.code, 2) << arg << "\n" << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << arg << "\n" << r.output;
    EXPECT_FALSE(fs::exists(png)) << arg;
  }
  const CliRun ok = dtfabric(base + tck.string() + ":3.5");
  EXPECT_EQ(ok.code, 0) << ok.output;
  EXPECT_NE(ok.output.find("the fabric along 1 streamlines of"), std::string::npos) << ok.output;
  EXPECT_TRUE(fs::exists(png));
  const CliRun view = dtfabric("view --fabric-along " + (dir / "missing.tck").string());
  EXPECT_EQ(view.code, 2) << view.output;
  EXPECT_NE(view.output.find("missing.tck"), std::string::npos) << view.output;
}
