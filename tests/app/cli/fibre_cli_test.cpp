// SPDX-License-Identifier: GPL-3.0-or-later
// The crossing-fibre commands through the real executable: `phantom crossing` in every fibre layout on RAS
// and LAS grids read back by `info --voxel --json` as the same world directions; `render` of a fibre set
// (FA surfaces refused without --tensor) and DTI beside the fibres with --split input=PEAKS.
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <algorithm>
#include <cmath>
#include <regex>

namespace fs = std::filesystem;
using dtf::test::runDtfabric;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// The "direction" triples of `info --json` in order.
std::vector<std::array<double, 3>> directions(const std::string& json) {
  std::vector<std::array<double, 3>> out;
  static const std::regex re(R"re("direction": \[([^,\]]+), ([^,\]]+), ([^,\]]+)\])re");
  for (auto it = std::sregex_iterator(json.begin(), json.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])});
  return out;
}

double angleTo(const std::array<double, 3>& d, double deg) {
  const double c = d[0] * std::cos(deg * M_PI / 180) + d[1] * std::sin(deg * M_PI / 180);
  return std::acos(std::min(1.0, std::abs(c))) * 180 / M_PI;
}

} // namespace

TEST(FibreCli, PhantomLayoutsReadBackAsTheSameWorldDirections) {
  const fs::path dir = dtf::test::scratchDir();
  for (const std::string grid : {"ras", "las"})
    for (const std::string layout : {"mrtrix-peaks", "dipy-peaks", "bedpostx"}) {
      SCOPED_TRACE(grid + " " + layout);
      const fs::path out = dir / (layout + "_" + grid + (layout == "bedpostx" ? "" : ".nii.gz"));
      auto w = runDtfabric("phantom crossing --crossing 70 --size 24 --grid " + grid + " --layout " + layout +
                               " -o " + q(out),
                           dir);
      ASSERT_EQ(w.exitCode, 0) << w.err;
      // The centre voxel lies in both bundles (at -35 and +35 degrees from +x in the axial plane).
      auto r = runDtfabric("info " + q(out) + " --voxel 12,12,12 --json", dir);
      ASSERT_EQ(r.exitCode, 0) << r.err;
      auto d = directions(r.out);
      ASSERT_EQ(d.size(), 2u) << r.out;
      const double a0 = std::min(angleTo(d[0], -35), angleTo(d[0], 35));
      const double a1 = std::min(angleTo(d[1], -35), angleTo(d[1], 35));
      EXPECT_LT(a0, 0.01) << r.out;
      EXPECT_LT(a1, 0.01) << r.out;
      // One fibre per bundle, amplitude 0.4 each where they overlap.
      EXPECT_LT(std::min(angleTo(d[0], -35) + angleTo(d[1], 35), angleTo(d[0], 35) + angleTo(d[1], -35)),
                0.02);
      EXPECT_NEAR(dtf::test::jsonNumber(r.out, "amplitude"), 0.4, 1e-6) << r.out;
      // An arm voxel: one fibre (bundle at -35 degrees runs through x > 0, y < 0).
      const int i = grid == "ras" ? 19 : 4; // world x = +7 mm either way
      auto arm = runDtfabric("info " + q(out) + " --voxel " + std::to_string(i) + ",7,12 --json", dir);
      ASSERT_EQ(arm.exitCode, 0) << arm.err;
      auto da = directions(arm.out);
      ASSERT_EQ(da.size(), 1u) << arm.out;
      EXPECT_LT(angleTo(da[0], -35), 0.01) << arm.out;
    }
}

TEST(FibreCli, RenderRefusesFaSurfacesWithoutATensorAndSplitsDtiBesidePeaks) {
  const fs::path dir = dtf::test::scratchDir();
  ASSERT_EQ(
      runDtfabric("phantom crossing --size 20 --layout mrtrix-peaks -o " + q(dir / "p.nii.gz"), dir).exitCode,
      0);
  ASSERT_EQ(runDtfabric("phantom crossing --size 20 -o " + q(dir / "t.nii.gz"), dir).exitCode, 0);
  auto fa =
      runDtfabric("render " + q(dir / "p.nii.gz") + " --fa 0.3 --size 64x64 -o " + q(dir / "fa.png"), dir);
  EXPECT_EQ(fa.exitCode, 1) << fa.err;
  EXPECT_NE(fa.err.find("--tensor"), std::string::npos) << fa.err;
  EXPECT_FALSE(fs::exists(dir / "fa.png"));
  auto paired = runDtfabric("render " + q(dir / "p.nii.gz") + " --tensor " + q(dir / "t.nii.gz") +
                                " --fa 0.3 --size 64x64 -o " + q(dir / "fa.png"),
                            dir);
  EXPECT_EQ(paired.exitCode, 0) << paired.err;
  auto split = runDtfabric("render " + q(dir / "t.nii.gz") + " --split input=" + (dir / "p.nii.gz").string() +
                               " --size 64x64 -o " + q(dir / "split.png"),
                           dir);
  ASSERT_EQ(split.exitCode, 0) << split.err;
  const dtf::Image img = dtf::io::readPng((dir / "split.png").string());
  EXPECT_EQ(img.width, 128);
  auto med = runDtfabric(
      "render " + q(dir / "p.nii.gz") + " --color medical --size 64x64 -o " + q(dir / "m.png"), dir);
  EXPECT_EQ(med.exitCode, 1) << med.err;
}

TEST(FibreCli, TensorCommandsRefuseAFibreSetByName) {
  const fs::path dir = dtf::test::scratchDir();
  ASSERT_EQ(
      runDtfabric("phantom crossing --size 16 --layout dipy-peaks -o " + q(dir / "p.nii.gz"), dir).exitCode,
      0);
  // Two peaks in 6 volumes: refused by the tensor reader; 9 volumes: refused as a fibre set before being
  // taken for a DWI.
  auto r = runDtfabric("surface " + q(dir / "p.nii.gz") + " --slice axial -o " + q(dir / "s.ply"), dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("p.nii.gz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a tensor"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "s.ply"));
  DTF_SHARED_FILE(peaks, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz"); // 9 volumes
  auto t = runDtfabric("surface " + q(peaks) + " --slice axial -o " + q(dir / "t.ply"), dir);
  EXPECT_EQ(t.exitCode, 2) << t.err;
  EXPECT_NE(t.err.find("a fibre set"), std::string::npos) << t.err;
  EXPECT_FALSE(fs::exists(dir / "t.ply"));
}

// DTI beside MRtrix peaks that carry no FA of their own: the peaks pane takes the tensor's FA (same grid),
// so grey matter is grey in both panes (the anatomy look's FA ramp). Without it the peaks pane wove full
// colour over every voxel. Measured on the pixels where the tensor pane shows grey matter (chroma, max - min
// of RGB, below 0.08): the peaks pane is mostly grey there too.
TEST(FibreCli, SplitPeaksPaneTakesTheTensorsFa) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(peaks, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  const fs::path dir = dtf::test::scratchDir();
  auto r = runDtfabric("render " + q(tensor) + " --split input=" + q(peaks) +
                           " --slice coronal:34 --size 256x256 -o " + q(dir / "split.png"),
                       dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("FA from " + tensor.string()), std::string::npos) << r.err;
  const dtf::Image img = dtf::io::readPng((dir / "split.png").string());
  ASSERT_EQ(img.width, 512);
  auto chroma = [&](int x, int y) {
    const std::uint8_t* p = img.pixel(x, y);
    return (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]})) / 255.0;
  };
  auto lit = [&](int x, int y) {
    const std::uint8_t* p = img.pixel(x, y);
    return p[0] + p[1] + p[2] > 60;
  };
  int grey = 0, greyInBoth = 0, colourful = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      if (!lit(x, y) || !lit(x + 256, y)) continue;
      const double left = chroma(x, y), right = chroma(x + 256, y);
      if (left < 0.08) {
        ++grey;
        if (right < 0.15) ++greyInBoth;
      }
      if (left > 0.35) colourful += right > 0.2 ? 1 : 0;
    }
  ASSERT_GT(grey, 3000) << "too little grey matter in the tensor pane";
  EXPECT_GT(greyInBoth, 0.6 * grey) << greyInBoth << " of " << grey;
  EXPECT_GT(colourful, 1000); // white matter keeps its colours in the peaks pane
}
