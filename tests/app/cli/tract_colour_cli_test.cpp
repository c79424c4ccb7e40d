// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric render --tracts-color/--tracts-range/--tracts-group` end to end on the sample phantom with a TRX
// made here: tracts take the colour map's colours (low end purple, high end yellow) instead of DEC, the
// colour bar at the right edge holds the map's end colours, and a group shows only its streamlines.
#include "io/formats/png_io.h"
#include "io/formats/trx.h"
#include "support/polylines.h"
#include "support/gl_test.h"
#include "support/window.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct CliRun {
  int code = -1;
  std::string output;
};

CliRun dtfabric(const std::string& args, const fs::path& dir) {
  const fs::path log = dir / "cli.log";
  const int status =
      std::system((std::string(DTF_EXE) + " " + args + " > " + log.string() + " 2>&1").c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  r.output.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

// Twelve straight lines through the centre (a fan), value 5 on every point; group "one" holds line 0.
dtf::Polylines fan() {
  dtf::Polylines l = dtf::test::fanLines();
  l.perPoint = {{"v", 1, std::vector<float>(l.points.size(), 5.0f)}};
  l.perLine = {{"id", 1, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}}};
  l.groups = {{"one", {0}}, {"all", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}}};
  return l;
}

// Pixels that differ from `base` (summed RGB above 60) left of the colour bar, and their mean colour.
struct Diff {
  std::size_t n = 0;
  glm::dvec3 mean{0.0};
};
Diff diff(const dtf::Image& img, const dtf::Image& base) {
  Diff d;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width - 20; ++x) {
      const auto *p = img.pixel(x, y), *q = base.pixel(x, y);
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) < 60) continue;
      ++d.n;
      d.mean += glm::dvec3(p[0], p[1], p[2]);
    }
  if (d.n) d.mean /= double(d.n);
  return d;
}

} // namespace

TEST(TractColourCli, ValueColoursBarAndGroups) {
  DTF_GL_TEST_SETUP();
  ASSERT_TRUE(fs::exists(kPhantom)) << kPhantom;
  const fs::path dir = dtf::test::scratchDir();
  const fs::path trx = dir / "fan.trx";
  dtf::Grid g = dtf::Grid::fromAffine({64, 64, 64}, glm::dmat4(1.0));
  dtf::io::writeTrx(trx.string(), fan(), g);
  const std::string common = "render " + kPhantom.string() + " --size 128x128 --force --tracts-near 0";
  auto render = [&](const std::string& name, const std::string& extra) {
    const fs::path out = dir / (name + ".png");
    const CliRun r = dtfabric(common + extra + " -o " + out.string(), dir);
    EXPECT_EQ(r.code, 0) << r.output;
    return std::make_pair(dtf::io::readPng(out.string()), r.output);
  };
  const dtf::Image none = render("none", "").first;
  const std::string tracts = " --tracts " + trx.string();
  // Value 5 mapped with range 0..1 -> the top of the map (yellow); with 10..11 -> the bottom (purple).
  // (The tracts' colours without the colour bar, whose labels are white.)
  const auto [high, highLog] = render("high", tracts + " --tracts-color v --tracts-range 0,1 --no-colour-bar");
  const auto [low, lowLog] = render("low", tracts + " --tracts-color v --tracts-range 10,11 --no-colour-bar");
  const dtf::Image withBar = render("bar", tracts + " --tracts-color v --tracts-range 0,1").first;
  EXPECT_NE(highLog.find("coloured by 'v' from 0 (bottom of the bar) to 1 (top)"), std::string::npos)
      << highLog;
  const Diff h = diff(high, none), l = diff(low, none);
  ASSERT_GT(h.n, 100u);
  ASSERT_GT(l.n, 100u);
  EXPECT_GT(h.mean.x, 1.5 * h.mean.z) << "yellow expected";
  EXPECT_GT(h.mean.y, 1.5 * h.mean.z) << "yellow expected";
  EXPECT_GT(l.mean.z, 1.5 * l.mean.y) << "purple expected";
  EXPECT_GT(l.mean.x, 1.5 * l.mean.y) << "purple expected";
  // The bar: 8 px wide at the right edge, beside the orientation letter's band (its width follows the
  // font), 51 px tall centred; top #fde725, bottom #440154. Its column is the rightmost top-colour pixel of
  // the top row in the right half.
  int barX = -1;
  for (int x = 127; x >= 64 && barX < 0; --x)
    if (withBar.pixel(x, 38)[0] == 0xfd && withBar.pixel(x, 38)[1] == 0xe7 && withBar.pixel(x, 38)[2] == 0x25)
      barX = x - 3;
  ASSERT_GE(barX, 64) << "no colour bar on row 38";
  const std::uint8_t* top = withBar.pixel(barX, 38);
  const std::uint8_t* bottom = withBar.pixel(barX, 88);
  EXPECT_NE(int(high.pixel(barX, 38)[0]), 0xfd); // --no-colour-bar: none
  EXPECT_EQ(int(top[0]), 0xfd);
  EXPECT_EQ(int(top[1]), 0xe7);
  EXPECT_EQ(int(top[2]), 0x25);
  EXPECT_EQ(int(bottom[0]), 0x44);
  EXPECT_EQ(int(bottom[1]), 0x01);
  EXPECT_EQ(int(bottom[2]), 0x54);
  // A per-streamline value colours whole lines: id 0..11 over 0..11 gives both ends of the map.
  const auto [byId, idLog] = render("id", tracts + " --tracts-color id");
  EXPECT_NE(idLog.find("from 0 (bottom of the bar) to 11 (top)"), std::string::npos) << idLog;
  EXPECT_GT(diff(byId, none).n, 100u);
  // Groups: one line shows fewer pixels than all twelve, and some.
  const std::size_t one = diff(render("one", tracts + " --tracts-group one").first, none).n;
  const std::size_t all = diff(render("all", tracts + " --tracts-group all").first, none).n;
  EXPECT_GT(one, 10u);
  EXPECT_LT(3 * one, all);
  // Unknown names are bad input naming what exists; the flags need --tracts.
  const CliRun bad = dtfabric(common + tracts + " --tracts-group ARC_X -o " + (dir / "x.png").string(), dir);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("no group 'ARC_X' (groups: 'all', 'one')"), std::string::npos) << bad.output;
  const CliRun badValue =
      dtfabric(common + tracts + " --tracts-color fa -o " + (dir / "x.png").string(), dir);
  EXPECT_EQ(badValue.code, 2);
  EXPECT_NE(badValue.output.find("'v'"), std::string::npos) << badValue.output;
  const CliRun usage = dtfabric(common + " --tracts-color v -o " + (dir / "x.png").string(), dir);
  EXPECT_EQ(usage.code, 1) << usage.output;
}
