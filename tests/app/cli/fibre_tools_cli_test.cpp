// SPDX-License-Identifier: GPL-3.0-or-later
// Other tools' fibre files through the real executable: a DSI Studio FIB and an FSL dtifit set with V1 but no
// eigenvalues are fibre sets for `info --voxel --json` (directions in world RAS, the file's own FA) and for
// `render` (an FA surface without --tensor).
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

std::vector<double> numbers(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + R"re(": \[?([-0-9.e]+)(?:, ([-0-9.e]+), ([-0-9.e]+)\])?)re");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return {};
  std::vector<double> out;
  for (std::size_t i = 1; i < m.size(); ++i)
    if (m[i].matched) out.push_back(std::stod(m[i]));
  return out;
}

} // namespace

TEST(FibreToolsCli, DsiStudioFibVoxelListsItsPopulationsAndDtiFa) {
  DTF_SHARED_FILE(fib, "niivue_other_tools/dsistudio.fib.gz");
  const fs::path dir = dtf::test::scratchDir();
  // Body of the corpus callosum: fa0 0.379 at odf vertex (-1, 0, 0) in LPS voxel axes, dti_fa 0.683.
  const auto r = runDtfabric("info " + q(fib) + " --voxel 36,37,17 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("\"fibre_layout\": \"dsi-studio\""), std::string::npos) << r.out;
  const std::vector<double> d = numbers(r.out, "direction"), a = numbers(r.out, "amplitude"),
                            fa = numbers(r.out, "fa");
  ASSERT_EQ(d.size(), 3u) << r.out;
  EXPECT_GT(std::abs(d[0]), 0.999) << r.out; // left-right in world RAS
  ASSERT_EQ(a.size(), 1u);
  EXPECT_NEAR(a[0], 0.379, 1e-3);
  ASSERT_EQ(fa.size(), 1u) << r.out;
  EXPECT_NEAR(fa[0], 0.683, 1e-3);
  const auto render = runDtfabric("render " + q(fib) + " --fa 0.4 --size 64x64 -o " + q(dir / "fa.png"), dir);
  EXPECT_EQ(render.exitCode, 0) << render.err;
  EXPECT_TRUE(fs::exists(dir / "fa.png"));
  EXPECT_NE(render.err.find("dti_fa"), std::string::npos) << render.err;
}

TEST(FibreToolsCli, DtifitV1SetVoxelIsOnePopulationInTheFslFrame) {
  DTF_SHARED_FILE(v1, "niivue_fsl_dtifit/V1.nii.gz");
  const fs::path dir = dtf::test::scratchDir();
  // Splenium: V1 (-0.996, -0.001, -0.084), FA 0.852; the grid is LAS (det < 0): world = (-x, y, z).
  const auto r = runDtfabric("info " + q(v1) + " --voxel 42,55,28 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("\"fibre_layout\": \"dtifit-v1\""), std::string::npos) << r.out;
  const std::vector<double> d = numbers(r.out, "direction"), a = numbers(r.out, "amplitude"),
                            fa = numbers(r.out, "fa");
  ASSERT_EQ(d.size(), 3u) << r.out;
  const double s = d[0] > 0 ? 1 : -1;
  EXPECT_NEAR(s * d[0], 0.996, 2e-3) << r.out;
  EXPECT_NEAR(s * d[1], -0.001, 2e-3) << r.out;
  EXPECT_NEAR(s * d[2], -0.084, 2e-3) << r.out;
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0], 1.0);
  ASSERT_EQ(fa.size(), 1u) << r.out;
  EXPECT_NEAR(fa[0], 0.852, 1e-3);
  const auto summary = runDtfabric("info " + q(v1), dir);
  ASSERT_EQ(summary.exitCode, 0) << summary.err;
  for (const char* s2 : {"dtifit-v1", "found V1, FA", "no L1-L3"})
    EXPECT_NE(summary.out.find(s2), std::string::npos) << s2 << " missing:\n" << summary.out;
  const auto render = runDtfabric("render " + q(v1) + " --fa 0.4 --size 64x64 -o " + q(dir / "fa.png"), dir);
  EXPECT_EQ(render.exitCode, 0) << render.err;
  EXPECT_TRUE(fs::exists(dir / "fa.png"));
}
