// The crossing-fibre commands through the real executable: `phantom crossing` in every fibre layout on RAS
// and LAS grids read back by `info --voxel --json` as the same world directions; `render` of a fibre set
// (FA surfaces refused without --tensor) and DTI beside the fibres with --split input=PEAKS.
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/test_env.h"

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
