// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre sets in the viewer scene (app/viewer/viewer.h), headless: a crossing fibre set weaves both bundles at
// the centre of the crossing; the same crossing as one tensor per voxel in the fibres colour mode (its
// principal direction, as `render --color fibres` shows a tensor) and in the medical mode weaves their
// average instead; the uploads follow a change of colour mode without reloading. The orientation histogram
// is the fibre render tests' check (support/orientation_histogram.h).
#include "app/viewer/viewer.h"
#include "io/formats/fibre_io.h"
#include "io/phantoms.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/gl_test.h"
#include "support/view_scene.h"

#include <string>

using namespace dtf;

namespace {

constexpr double kCrossing = 60; // bundles at -30 and +30 degrees from +x in the axial plane

io::PhantomOptions crossing() {
  io::PhantomOptions o; // 64 voxels of 1 mm
  o.crossingDeg = kCrossing;
  return o;
}

// The centre of the crossing after convergence (zoomed to about 13 mm, inside the overlap of the bundles),
// and its histogram's peaks.
std::vector<double> centrePeaks(test::ViewScene& s, const char* name, std::array<double, test::kBins>* hist) {
  s.apply(session::Zoom{5});
  s.converge();
  const Image img = s.image();
  if (test::envFlag("DTF_TEST_SAVE_IMAGES")) io::writePng((test::binaryDir() / name).string(), img);
  *hist = test::orientationHistogram(img, 40, 40, 216, 216);
  return test::peaks(*hist, 0.3);
}

std::string list(const std::vector<double>& p) {
  std::string s;
  for (double x : p)
    s += std::to_string(x) + " ";
  return s;
}

} // namespace

TEST(ViewFibresScene, ACrossingFibreSetWeavesBothBundles) {
  DTF_GL_TEST_SETUP();
  const auto dir = test::scratchDir();
  const std::string peaks = (dir / "x60_peaks.nii.gz").string();
  io::writeFibres(peaks, io::makeFibrePhantom("crossing", crossing()), io::FibreLayout::DipyPeaks);
  test::ViewScene s("slice=axial");
  s.apply(session::LoadFile{peaks});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  ASSERT_TRUE(s.state().fibres.present);
  EXPECT_EQ(s.state().fabric.colour, render::ColourMode::Fibres);
  std::array<double, test::kBins> h{};
  const auto p = centrePeaks(s, "view_fibres_crossing.png", &h);
  EXPECT_LT(test::nearestPeak(p, 30.0), 5.0) << "peaks: " << list(p);
  EXPECT_LT(test::nearestPeak(p, -30.0), 5.0) << "peaks: " << list(p);
  EXPECT_LT(test::binValue(h, 0.0), 0.5 * std::min(test::binValue(h, 30.0), test::binValue(h, -30.0)))
      << "peaks: " << list(p) << " at 0: " << test::binValue(h, 0.0) << ", -30: " << test::binValue(h, -30.0)
      << ", 30: " << test::binValue(h, 30.0);
}

TEST(ViewFibresScene, ATensorInTheFibresModeShowsItsPrincipalDirectionLikeTheMedicalMode) {
  DTF_GL_TEST_SETUP();
  const auto dir = test::scratchDir();
  const std::string tensor = (dir / "x60_tensor.nii.gz").string();
  io::writeTensorVolume(tensor, io::makePhantom("crossing", crossing()).tensors, io::TensorLayout::Fsl);
  test::ViewScene s("slice=axial");
  s.apply(session::LoadFile{tensor});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.state().fabric.colour, render::ColourMode::Medical);
  std::array<double, test::kBins> medical{};
  const auto pm = centrePeaks(s, "view_fibres_tensor_medical.png", &medical); // zooms in
  // The same field in the fibres mode: uploaded as one population (the principal direction) on the fly.
  render::FabricParams params = s.state().fabric;
  params.colour = render::ColourMode::Fibres;
  s.apply(session::SetFabricParams{params});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  std::array<double, test::kBins> fibres{};
  const Image img = s.image();
  if (test::envFlag("DTF_TEST_SAVE_IMAGES"))
    io::writePng((test::binaryDir() / "view_fibres_tensor_principal.png").string(), img);
  fibres = test::orientationHistogram(img, 40, 40, 216, 216);
  const auto pf = test::peaks(fibres, 0.3);
  // Both weave the tensor average (the bisector, 0 degrees), neither bundle.
  EXPECT_LT(test::nearestPeak(pm, 0.0), 6.0) << "medical peaks: " << list(pm);
  EXPECT_LT(test::nearestPeak(pf, 0.0), 6.0) << "fibres-mode peaks: " << list(pf);
  EXPECT_LT(test::binValue(fibres, 30.0), 0.5) << "fibres-mode peaks: " << list(pf);
  // Back to medical: the principal-direction upload is dropped again and the image is the medical one.
  params.colour = render::ColourMode::Medical;
  s.apply(session::SetFabricParams{params});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const auto again = test::orientationHistogram(s.image(), 40, 40, 216, 216);
  EXPECT_LT(test::nearestPeak(test::peaks(again, 0.3), 0.0), 6.0);
}
