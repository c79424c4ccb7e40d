// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric render --tracts/--split` end to end: the PNG has the right size (2W x H for a split), the same
// arguments give the same bytes, and a bad tract file is exit 2 naming the file.
#include "io/formats/png_io.h"
#include "io/formats/tracts.h"
#include "support/polylines.h"
#include "support/cli.h"
#include "support/gl_test.h"
#include "support/window.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

using dtf::test::CliRun;

CliRun dtfabric(const std::string& args, const fs::path& dir) {
  return dtf::test::runDtfabricCombined(args, dir / "cli.log");
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

// A fan of straight tracts through the phantom's centre region (world mm).
dtf::Polylines fan() {
  dtf::Polylines l = dtf::test::fanLines();
  return l;
}

} // namespace

TEST(TractRenderCli, OverlayAndSplitWriteTheSamePngTwice) {
  DTF_GL_TEST_SETUP();
  ASSERT_TRUE(fs::exists(kPhantom)) << kPhantom;
  const fs::path dir = dtf::test::scratchDir();
  const fs::path tck = dir / "fan.tck";
  dtf::io::writeTck(tck.string(), fan());
  const std::string common =
      kPhantom.string() + " --size 96x80 --tracts " + tck.string() + " --tracts-near 0";
  const std::string second = " --split input=" + kPhantom.string();
  const std::string splits[] = {"", " --split tracts", " --split colour", " --split surface=fa=0.25", second};
  for (const std::string& split : splits) {
    SCOPED_TRACE(split);
    const fs::path a = dir / "a.png", b = dir / "b.png";
    CliRun r1 = dtfabric("render " + common + split + " --force -o " + a.string(), dir);
    ASSERT_EQ(r1.code, 0) << r1.output;
    CliRun r2 = dtfabric("render " + common + split + " --force -o " + b.string(), dir);
    ASSERT_EQ(r2.code, 0) << r2.output;
    dtf::Image img = dtf::io::readPng(a.string());
    EXPECT_EQ(img.width, split.empty() ? 96 : 192);
    EXPECT_EQ(img.height, 80);
    EXPECT_EQ(bytes(a), bytes(b));
    if (!split.empty()) {
      // The seam: a grey line two pixels wide over the panes' facing edges.
      for (int y : {0, 40, 79})
        for (int x : {95, 96})
          EXPECT_EQ(int(img.pixel(x, y)[0]), 90) << x << "," << y;
      EXPECT_NE(int(img.pixel(94, 0)[0]), 90);
    }
    if (split == " --split tracts") {
      // Left pane the fabric alone, right pane with the fan: they differ (the seam's columns left out).
      std::size_t changed = 0;
      for (int y = 0; y < 80; ++y)
        for (int x = 1; x < 95; ++x)
          changed += !std::equal(img.pixel(x, y), img.pixel(x, y) + 3, img.pixel(x + 96, y));
      EXPECT_GT(changed, 50u);
    }
  }
}

TEST(TractRenderCli, BadTractFileIsExit2NamingIt) {
  DTF_GL_TEST_SETUP();
  const fs::path dir = dtf::test::scratchDir();
  const fs::path bad = dir / "broken.tck";
  std::ofstream(bad) << "mrtrix tracks\nnot really\n";
  CliRun r = dtfabric("render " + kPhantom.string() + " --size 64x64 --tracts " + bad.string() + " -o " +
                          (dir / "out.png").string(),
                      dir);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("broken.tck"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out.png"));
  CliRun u = dtfabric("render " + kPhantom.string() + " --split tracts -o " + (dir / "u.png").string(), dir);
  EXPECT_EQ(u.code, 1) << u.output;
}

// The camera-facing clip slab on a curved surface (the viewer's clip): a slab through the brain's centre
// keeps a part of the tracts, one moved beyond the brain along the view keeps none.
TEST(TractRenderCli, ClipSlabOnACurvedSurfaceFollowsItsDepth) {
  DTF_GL_TEST_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = dtf::test::scratchDir();
  const std::string common = "render " + tensor.string() + " --surface fa=0.25 --size 256x256 --force";
  auto render = [&](const std::string& name, const std::string& extra) {
    const fs::path out = dir / (name + ".png");
    const CliRun r = dtfabric(common + extra + " -o " + out.string(), dir);
    EXPECT_EQ(r.code, 0) << r.output;
    return dtf::io::readPng(out.string());
  };
  const dtf::Image none = render("none", "");
  const std::string tracts = " --tracts " + tck.string() + " --tracts-near 0";
  const std::size_t all = dtf::test::tractPixels(render("all", tracts), none);
  const std::size_t centre = dtf::test::tractPixels(render("centre", tracts + " --tracts-slab 4"), none);
  const std::size_t beyond =
      dtf::test::tractPixels(render("beyond", tracts + " --tracts-slab 4 --tracts-slab-depth 200"), none);
  EXPECT_GT(all, 2000u);
  EXPECT_LT(centre, all * 2 / 3);
  EXPECT_GT(centre, all / 50);
  EXPECT_LT(beyond, all / 200) << "a slab outside the brain shows no tract";
  const CliRun bad =
      dtfabric(common + tracts + " --tracts-slab-depth 5000 -o " + (dir / "x.png").string(), dir);
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("--tracts-slab-depth must be in [-1000, 1000] mm"), std::string::npos)
      << bad.output;
}
