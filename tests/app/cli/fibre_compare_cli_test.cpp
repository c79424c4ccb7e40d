// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric compare` with a fibre set: the crossing phantom written by `dtfabric phantom crossing` as tensors
// and as peak files in every layout, tracts along either bundle (written here) compared on the axial slice
// through the crossing. Against the fibre set every point agrees (the nearest population is the tract's own
// bundle); against the tensor the points inside the crossing are 30 degrees off (its principal direction is
// the average). Bad input (mismatched grid, missing file) exits 2 naming the file.
#include "io/model/geometry.h"
#include "io/formats/tracts.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>

namespace fs = std::filesystem;
using dtf::test::jsonNumber;
using dtf::test::runDtfabric;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

class FibreCompareCli : public ::testing::Test {
protected:
  void SetUp() override { dir_ = dtf::test::scratchDir(); }

  // `phantom crossing --crossing 60` in `layout` on `grid`; the path written.
  fs::path phantom(const std::string& layout, const std::string& grid, int size = 48) {
    const fs::path out = dir_ / ("x60_" + grid + "_" + layout + std::to_string(size) +
                                 (layout == "bedpostx" ? "" : ".nii.gz"));
    const auto r = runDtfabric("phantom crossing --crossing 60 --size " + std::to_string(size) + " --grid " +
                                   grid + " --layout " + layout + " -o " + q(out) + " --force",
                               dir_);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return out;
  }

  // Two straight tracts through the grid centre along the bundles (-30 and +30 degrees from x) in the axial
  // plane of the middle slice (world z 0.5 mm: the grid of an even size is centred between voxels).
  fs::path tracts() {
    dtf::Polylines lines;
    lines.offsets = {0};
    for (double az : {-30.0, 30.0}) {
      const double c = std::cos(az * M_PI / 180), s = std::sin(az * M_PI / 180);
      for (double t = -18; t <= 18 + 1e-9; t += 0.5)
        lines.points.emplace_back(static_cast<float>(t * c), static_cast<float>(t * s), 0.5f);
      lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
    }
    const fs::path out = dir_ / "bundles.tck";
    dtf::io::writeTck(out.string(), lines);
    return out;
  }

  dtf::test::CliResult compare(const fs::path& input, const std::string& extra = "") {
    return runDtfabric("compare " + q(input) + " --tracts " + q(tracts()) +
                           " --surface slice=axial:24 --json " + extra,
                       dir_);
  }

  fs::path dir_;
};

} // namespace

TEST_F(FibreCompareCli, TractsAlongEitherBundleAgreeWithTheFibreSetNotTheTensor) {
  const auto tensor = compare(phantom("fsl", "ras"));
  ASSERT_EQ(tensor.exitCode, 0) << tensor.err;
  EXPECT_NE(tensor.out.find("\"against\": \"tensor principal direction\""), std::string::npos) << tensor.out;
  const double points = jsonNumber(tensor.out, "points");
  EXPECT_GT(points, 100);
  // Tensor: a third of each tract lies in the crossing, 30 degrees from the average direction there.
  EXPECT_LT(jsonNumber(tensor.out, "frac_below_15"), 0.85) << tensor.out;
  EXPECT_GT(jsonNumber(tensor.out, "mean_deg"), 5.0) << tensor.out;

  for (const std::string grid : {"ras", "las"})
    for (const std::string layout : {"mrtrix-peaks", "dipy-peaks", "bedpostx"}) {
      SCOPED_TRACE(grid + " " + layout);
      const auto fibres = compare(phantom(layout, grid));
      ASSERT_EQ(fibres.exitCode, 0) << fibres.err;
      EXPECT_NE(fibres.out.find("\"against\": \"nearest fibre population\""), std::string::npos)
          << fibres.out;
      EXPECT_EQ(jsonNumber(fibres.out, "points"), points) << fibres.out;
      EXPECT_GT(jsonNumber(fibres.out, "frac_below_15"), 0.999) << fibres.out;
      EXPECT_LT(jsonNumber(fibres.out, "mean_deg"), 2.0) << fibres.out;
      EXPECT_LT(jsonNumber(fibres.out, "median_deg"), 1.0) << fibres.out;
    }

  // The text report says what the tracts were measured against.
  const auto text = runDtfabric("compare " + q(phantom("mrtrix-peaks", "ras")) + " --tracts " + q(tracts()) +
                                    " --surface slice=axial:24",
                                dir_);
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("against: the nearest fibre population"), std::string::npos) << text.out;
}

// With the paired tensor (--tensor) an FA isosurface of the fibre set can be compared (at 0.5, so the
// closest surface points have most of their interpolation weight on voxels with fibres: at the data's edge
// a point with less than half is skipped); a tensor on another
// grid, a missing peaks file and a missing tensor exit 2 naming the file; bad options exit 1.
TEST_F(FibreCompareCli, PairedTensorAndBadInput) {
  const fs::path peaks = phantom("mrtrix-peaks", "ras"), tensor = phantom("fsl", "ras");
  auto r = compare(peaks, "--tensor " + q(tensor));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_GT(jsonNumber(r.out, "frac_below_15"), 0.999) << r.out;
  r = runDtfabric("compare " + q(peaks) + " --tensor " + q(tensor) + " --tracts " + q(tracts()) +
                      " --surface fa=0.5 --near 10 --json",
                  dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_GT(jsonNumber(r.out, "points"), 50) << r.out; // the bundles' faces, 9.4 mm above and below
  EXPECT_GT(jsonNumber(r.out, "frac_below_15"), 0.9) << r.out;
  // Without a tensor, fa= needs FA the peaks file does not have: a usage error naming the surface.
  r = runDtfabric("compare " + q(peaks) + " --tracts " + q(tracts()) + " --surface fa=0.3", dir_);
  EXPECT_EQ(r.exitCode, 1) << r.err;

  const fs::path other = phantom("fsl", "ras", 40);
  r = compare(peaks, "--tensor " + q(other));
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find(other.string()), std::string::npos) << r.err;

  const fs::path missingPeaks = dir_ / "no_such_peaks.nii.gz";
  r = compare(missingPeaks, "--layout mrtrix-peaks");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find(missingPeaks.string()), std::string::npos) << r.err;

  const fs::path missingTensor = dir_ / "no_such_tensor.nii.gz";
  r = compare(peaks, "--tensor " + q(missingTensor));
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find(missingTensor.string()), std::string::npos) << r.err;

  EXPECT_EQ(compare(peaks, "--fibre-threshold 1.5").exitCode, 1);
  EXPECT_EQ(compare(tensor, "--tensor " + q(tensor)).exitCode, 1) << "--tensor with a tensor INPUT";
}
