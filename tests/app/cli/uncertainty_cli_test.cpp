// SPDX-License-Identifier: GPL-3.0-or-later
// Uncertainty through the real executable: `fit --bootstrap N --cone --fa-sd` on the bundled brain (cone in
// degrees where the mask is, NaN outside, narrow in the corpus callosum and wide at the ventricles), `info
// --voxel --uncertainty`, `render --uncertainty` (a legend, frayed pixels, the plain image unchanged without
// it) with a cone map and with a bedpostx folder, and bad usage (exit 1) or a bad map (exit 2, file named).
#include "io/formats/fibre_io.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>
#include <gtest/gtest.h>
#include <unistd.h>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// One bootstrap of the bundled brain shared by the tests of this file (20 resamples keep it quick).
struct Fitted {
  fs::path dir, tensor, cone, faSd;
  test::CliResult run;
};
const Fitted& fitted() {
  static const Fitted f = [] {
    Fitted r;
    // One folder per test process: ctest runs this file's cases in parallel processes.
    r.dir = test::binaryDir() / "test_scratch" / ("uncertainty_cli_" + std::to_string(::getpid()));
    fs::remove_all(r.dir);
    fs::create_directories(r.dir);
    r.tensor = r.dir / "dti.nii.gz";
    r.cone = r.dir / "cone.nii.gz";
    r.faSd = r.dir / "fasd.nii.gz";
    r.run = test::runDtfabric("fit " + q(test::sourceDir() / "sample_data" / "dwi.nii.gz") +
                                  " --bootstrap 20 --cone " + q(r.cone) + " --fa-sd " + q(r.faSd) + " -o " +
                                  q(r.tensor) + " --threads 2",
                              r.dir);
    return r;
  }();
  return f;
}

} // namespace

TEST(UncertaintyCli, FitWritesConeAndFaSpreadOnTheDwiGrid) {
  const Fitted& f = fitted();
  ASSERT_EQ(f.run.exitCode, 0) << f.run.err;
  EXPECT_NE(f.run.out.find("95 % cone of uncertainty"), std::string::npos) << f.run.out;
  EXPECT_NE(f.run.err.find("wild bootstrap: 20 resamples"), std::string::npos) << f.run.err;
  const ScalarVolume cone = io::readScalarVolume(f.cone.string());
  const ScalarVolume faSd = io::readScalarVolume(f.faSd.string());
  const auto tensors = io::readTensorVolume(f.tensor.string());
  ASSERT_EQ(cone.grid.dims, tensors.field.grid.dims);
  ASSERT_EQ(cone.components, 1);
  std::size_t inside = 0;
  for (std::size_t v = 0; v < cone.data.size(); ++v) {
    const bool valid = tensors.field.valid[v] != 0;
    EXPECT_EQ(std::isnan(cone.data[v]), !valid) << "voxel " << v;
    if (!valid) continue;
    ++inside;
    EXPECT_GE(cone.data[v], 0.0f);
    EXPECT_LE(cone.data[v], 90.0f);
    EXPECT_GE(faSd.data[v], 0.0f);
  }
  EXPECT_GT(inside, 40000u);
  // Anatomy (LAS grid 72x72x39, 3 mm): the corpus callosum on the midline at voxel (36, 42, 22) (FA 0.84,
  // e1 left-right) is certain; the lateral ventricle beside it at (39, 40, 22) (FA 0.10, CSF) is not.
  EXPECT_LT(cone.data[cone.grid.index(36, 42, 22)], 5.0f) << "corpus callosum";
  EXPECT_GT(cone.data[cone.grid.index(39, 40, 22)], 30.0f) << "ventricle";
}

TEST(UncertaintyCli, InfoReportsTheVoxelsCone) {
  const Fitted& f = fitted();
  ASSERT_EQ(f.run.exitCode, 0) << f.run.err;
  const auto r =
      test::runDtfabric("info " + q(f.tensor) + " --voxel 36,42,22 --uncertainty " + q(f.cone), f.dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("cone95:"), std::string::npos) << r.out;
  const auto j =
      test::runDtfabric("info " + q(f.tensor) + " --voxel 36,42,22 --json --uncertainty " + q(f.cone), f.dir);
  ASSERT_EQ(j.exitCode, 0) << j.err;
  const ScalarVolume cone = io::readScalarVolume(f.cone.string());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(j.out, m, std::regex(R"("cone_deg":\s*\[\s*([0-9.eE+-]+)\s*\])"))) << j.out;
  EXPECT_NEAR(std::stod(m[1]), cone.data[cone.grid.index(36, 42, 22)], 1e-4);
  const auto usage = test::runDtfabric("info " + q(f.tensor) + " --uncertainty " + q(f.cone), f.dir);
  EXPECT_EQ(usage.exitCode, 1) << usage.err;
}

TEST(UncertaintyCli, RenderFraysWithAConeMapAndWithABedpostxFolder) {
  const Fitted& f = fitted();
  ASSERT_EQ(f.run.exitCode, 0) << f.run.err;
  const std::string base = "render " + q(f.tensor) + " --surface slice=axial:22 --size 256x256 --force -o ";
  const auto plain = test::runDtfabric(base + q(f.dir / "plain.png"), f.dir);
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  const auto frayed =
      test::runDtfabric(base + q(f.dir / "frayed.png") + " --uncertainty " + q(f.cone), f.dir);
  ASSERT_EQ(frayed.exitCode, 0) << frayed.err;
  // The default anatomy look fades the fabric where the cone is widest (low FA): it says where the fraying
  // shows; the plain look does not need the note.
  EXPECT_NE(frayed.err.find("--look plain shows it everywhere"), std::string::npos) << frayed.err;
  const auto plainLook = test::runDtfabric(base + q(f.dir / "frayed_plain.png") + " --look plain --uncertainty " +
                                               q(f.cone),
                                           f.dir);
  ASSERT_EQ(plainLook.exitCode, 0) << plainLook.err;
  EXPECT_EQ(plainLook.err.find("--look plain shows it everywhere"), std::string::npos) << plainLook.err;
  const Image a = io::readPng((f.dir / "plain.png").string()),
              b = io::readPng((f.dir / "frayed.png").string());
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  // The legend: white text at the bottom-left where the plain image is dark background.
  int legend = 0, changed = 0;
  for (int y = 200; y < 256; ++y)
    for (int x = 0; x < 90; ++x)
      legend += b.pixel(x, y)[0] > 200 && b.pixel(x, y)[1] > 200 && a.pixel(x, y)[0] < 60;
  for (std::size_t i = 0; i < a.rgba.size(); ++i)
    changed += a.rgba[i] != b.rgba[i];
  EXPECT_GT(legend, 50);
  EXPECT_GT(changed, 5000);

  // A bedpostx folder: samples spread by 30 degrees around the tensor field's grid x axis, everywhere.
  const fs::path bp = f.dir / "subject.bedpostX";
  fs::create_directories(bp);
  const Grid g = io::readScalarVolume(f.cone.string()).grid;
  const int n = 8;
  ScalarVolume th(g, n), ph(g, n), fr(g, n, 0.6f);
  for (std::size_t v = 0; v < g.voxelCount(); ++v)
    for (int s = 0; s < n; ++s) {
      th.data[v * n + s] = static_cast<float>(glm::radians(90.0 - 30.0 * ((s % 2) ? 1 : -1)));
      ph.data[v * n + s] = 0.0f;
    }
  io::writeScalarVolume((bp / "merged_th1samples.nii.gz").string(), th);
  io::writeScalarVolume((bp / "merged_ph1samples.nii.gz").string(), ph);
  io::writeScalarVolume((bp / "merged_f1samples.nii.gz").string(), fr);
  const auto viaBedpostx =
      test::runDtfabric(base + q(f.dir / "bedpostx.png") + " --uncertainty " + q(bp), f.dir);
  ASSERT_EQ(viaBedpostx.exitCode, 0) << viaBedpostx.err;
  const auto info =
      test::runDtfabric("info " + q(f.tensor) + " --voxel 36,42,22 --uncertainty " + q(bp), f.dir);
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("cone95:       30 deg"), std::string::npos) << info.out;
}

TEST(UncertaintyCli, BadUsageAndBadMaps) {
  const Fitted& f = fitted();
  ASSERT_EQ(f.run.exitCode, 0) << f.run.err;
  const std::string dwi = q(test::sourceDir() / "sample_data" / "dwi.nii.gz");
  auto r = test::runDtfabric(
      "fit " + dwi + " --cone " + q(f.dir / "c.nii.gz") + " -o " + q(f.dir / "t.nii.gz"), f.dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_NE(r.err.find("--bootstrap"), std::string::npos) << r.err;
  r = test::runDtfabric("fit " + dwi + " --bootstrap 10 -o " + q(f.dir / "t.nii.gz"), f.dir);
  EXPECT_EQ(r.exitCode, 1) << r.err;
  r = test::runDtfabric("fit " + dwi + " --bootstrap 10 --cone " + dwi + " -o " + q(f.dir / "t.nii.gz"),
                        f.dir);
  EXPECT_NE(r.exitCode, 0) << "must never overwrite an input";
  // A 4D volume as a cone map: exit 2, the file named.
  r = test::runDtfabric("render " + q(f.tensor) + " --surface slice=axial:22 --size 64x64 --force -o " +
                            q(f.dir / "bad.png") + " --uncertainty " + q(f.tensor),
                        f.dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find(f.tensor.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cone map is 3D"), std::string::npos) << r.err;
}
