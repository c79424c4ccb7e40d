// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's figure, headless: the anatomy beneath the fabric (a DWI's mean b=0 image by default, any scalar
// volume on another grid with SetBackground, resampled in world space, none on request) and the furniture
// `render` draws (DEC orientation legend, scale bar, uncertainty legend), each switchable, in the exported
// scene.
#include "io/diffusion/dwi.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/gl_test.h"
#include "support/view_scene.h"

#include <cmath>

namespace {

using namespace dtf;

// The world point of scene pixel (x, y) of pane 0 on the plane through the camera's target (orthographic).
glm::dvec3 worldOf(const app::ViewerScene& s, int x, int y) {
  const render::Camera& c = s.camera(0);
  const auto r = s.paneRect(0);
  const glm::dvec3 right = c.right(), up = glm::normalize(glm::cross(right, c.forward()));
  const double mm = 2.0 * c.orthoHalfHeight / r[3];
  return c.target + right * ((x + 0.5 - r[0] - 0.5 * r[2]) * mm) - up * ((y + 0.5 - r[1] - 0.5 * r[3]) * mm);
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0, sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / a.size();
    mb += b[i] / b.size();
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Unsaturated pixels of the pane's middle (away from the furniture) against f(world point).
double greyCorrelation(const app::ViewerScene& s, const Image& img, const std::function<double(glm::dvec3)>& f,
                       std::size_t& count) {
  std::vector<double> a, b;
  for (int y = img.height / 6; y < img.height * 5 / 6; ++y)
    for (int x = img.width / 6; x < img.width * 5 / 6; ++x) {
      const auto* c = img.pixel(x, y);
      if (std::max({c[0], c[1], c[2]}) - std::min({c[0], c[1], c[2]}) > 3 || c[0] < 8) continue;
      const double v = f(worldOf(s, x, y));
      if (!std::isfinite(v)) continue;
      a.push_back(c[0]);
      b.push_back(v);
    }
  count = a.size();
  return a.size() > 10 ? correlation(a, b) : 0.0;
}

// Pixels of r (x, y, w, h) whose colour is one of the legend's DEC colours (saturated red, green or blue).
int decPixels(const Image& img, const std::array<int, 4>& r) {
  int n = 0;
  for (int y = r[1]; y < r[1] + r[3]; ++y)
    for (int x = r[0]; x < r[0] + r[2]; ++x) {
      const auto* c = img.pixel(x, y);
      n += (c[0] == 230 && c[1] == 40 && c[2] == 40) || (c[0] == 40 && c[1] == 210 && c[2] == 40) ||
           (c[0] == 60 && c[1] == 90 && c[2] == 255);
    }
  return n;
}

int whitePixels(const Image& img, const std::array<int, 4>& r) {
  int n = 0;
  for (int y = r[1]; y < r[1] + r[3]; ++y)
    for (int x = r[0]; x < r[0] + r[2]; ++x)
      n += img.pixel(x, y)[0] == 255 && img.pixel(x, y)[1] == 255 && img.pixel(x, y)[2] == 255;
  return n;
}

} // namespace

TEST(ViewFigure, ADwiShowsItsMeanB0BeneathAndAnotherGridsVolumeOnRequest) {
  DTF_GL_TEST_SETUP();
  const std::string dwi = (test::sourceDir() / "sample_data" / "dwi.nii.gz").string();
  test::ViewScene v("slice=axial");
  v.apply(session::LoadFile{dwi, "auto"});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  ASSERT_EQ(v.state().background, "mean b=0");
  ASSERT_TRUE(v.scene.background());

  // The mean b=0 image, independently: the volumes with b <= 50.
  const ScalarVolume signal = io::readScalarVolume(dwi);
  const std::vector<double> bvals = io::readBvals(io::gradientSibling(dwi, ".bval"));
  ScalarVolume b0(signal.grid, 1);
  for (int k = 0; k < signal.components; ++k)
    if (bvals[std::size_t(k)] <= 50)
      for (std::size_t i = 0; i < b0.data.size(); ++i)
        b0.data[i] += signal.data[i * std::size_t(signal.components) + std::size_t(k)];
  auto nearestB0 = [&](const glm::dvec3& w) {
    const glm::dvec3 ijk = glm::round(b0.grid.toVoxel(w));
    if (glm::any(glm::lessThan(ijk, glm::dvec3(0))) || glm::any(glm::greaterThanEqual(ijk, glm::dvec3(b0.grid.dims))))
      return std::nan("");
    return double(b0.data[b0.grid.index(int(ijk.x), int(ijk.y), int(ijk.z))]);
  };
  if (test::envFlag("DTF_TEST_SAVE_IMAGES")) io::writePng((test::binaryDir() / "view_figure_b0.png").string(), v.scene.layoutImage());
  std::size_t n = 0;
  const double rB0 = greyCorrelation(v.scene, v.scene.layoutImage(), nearestB0, n);
  std::printf("mean b=0 beneath: %zu grey pixels, correlation %.3f\n", n, rB0);
  EXPECT_GT(n, 2000u);
  EXPECT_GT(rB0, 0.8);

  // A volume on another grid (coarser, rotated 20 degrees about z, shifted): its world-space values show.
  const auto dir = test::scratchDir();
  glm::dmat4 affine = glm::rotate(glm::dmat4(1.0), glm::radians(20.0), glm::dvec3(0, 0, 1)) *
                      glm::scale(glm::dmat4(1.0), glm::dvec3(4.5));
  const glm::dvec3 centre = 0.5 * (v.scene.dataset()->lo + v.scene.dataset()->hi);
  affine[3] = glm::dvec4(centre - glm::dvec3(affine * glm::dvec4(15, 15, 15, 0)) + glm::dvec3(3, -2, 1), 1);
  ScalarVolume t1(Grid::fromAffine({30, 30, 30}, affine), 1);
  auto smooth = [&](const glm::dvec3& w) {
    return 100.0 + 60.0 * std::sin((w.x - centre.x) / 14.0) * std::cos((w.y - centre.y) / 19.0);
  };
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 30; ++j)
      for (int i = 0; i < 30; ++i)
        t1.data[t1.grid.index(i, j, k)] = float(smooth(t1.grid.toWorld(glm::dvec3(i, j, k))));
  const std::string t1Path = (dir / "t1.nii.gz").string();
  io::writeScalarVolume(t1Path, t1);
  v.apply(session::SetBackground{t1Path, ""});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  EXPECT_EQ(v.state().background, t1Path);
  if (test::envFlag("DTF_TEST_SAVE_IMAGES")) io::writePng((test::binaryDir() / "view_figure_t1.png").string(), v.scene.layoutImage());
  // Within the volume's grid, a voxel from its faces (the viewer's slices cover the DWI's whole grid, beyond
  // this volume; outside it and across its last half voxel nothing of it shows).
  auto smoothInside = [&](const glm::dvec3& w) {
    const glm::dvec3 ijk = t1.grid.toVoxel(w);
    return glm::all(glm::greaterThanEqual(ijk, glm::dvec3(1.0))) &&
                   glm::all(glm::lessThanEqual(ijk, glm::dvec3(28.0)))
               ? smooth(w)
               : std::nan("");
  };
  const double rT1 = greyCorrelation(v.scene, v.scene.layoutImage(), smoothInside, n);
  const double rT1vsB0 = greyCorrelation(v.scene, v.scene.layoutImage(), nearestB0, n);
  std::printf("another grid's volume beneath: %zu grey pixels, correlation %.3f (with the b=0 image %.3f)\n", n,
              rT1, rT1vsB0);
  EXPECT_GT(n, 2000u);
  EXPECT_GT(rT1, 0.9);
  EXPECT_LT(rT1vsB0, 0.5);

  // none: FA within the data, nothing uploaded; a missing file is an error naming it, the view unchanged.
  v.apply(session::SetBackground{"none", ""});
  v.converge();
  EXPECT_FALSE(v.scene.background());
  EXPECT_EQ(v.state().background, "");
  v.apply(session::SetBackground{(dir / "missing.nii.gz").string(), ""});
  v.frame();
  ASSERT_FALSE(v.state().errorChain.empty());
  EXPECT_NE(v.lastError().find("missing.nii.gz"), std::string::npos) << v.lastError();
}

TEST(ViewFigure, LegendScaleBarAndUncertaintyLegendAreDrawnWhereAskedAndSwitchOff) {
  DTF_GL_TEST_SETUP();
  const std::string phantom = (test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();
  test::ViewScene v("slice=axial");
  v.apply(session::LoadFile{phantom, "auto"});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  const int w = 256, h = 256;
  const std::array<int, 4> legendBox{w - 60, h - 60, 60, 60}, barBox{0, h - 30, w / 3, 30},
      frayBox{0, h - 80, 110, 80};
  const Image on = v.scene.layoutImage();
  EXPECT_GT(decPixels(on, legendBox), 20);
  EXPECT_GT(whitePixels(on, barBox), 20);
  v.apply(session::SetFurniture{false, false, {}});
  v.frame();
  const Image off = v.scene.layoutImage();
  EXPECT_EQ(decPixels(off, legendBox), 0);
  EXPECT_LT(whitePixels(off, barBox), whitePixels(on, barBox) / 4);
  // The uncertainty legend bottom-left; the scale bar, on again, steps above it.
  v.apply(session::SetFurniture{{}, true, {}});
  session::UncertaintyMap cone;
  cone.cone = ScalarVolume(v.scene.dataset()->loaded.field.grid, 1, 20.0f);
  v.scene.setUncertainty(cone);
  v.converge();
  const Image fray = v.scene.layoutImage();
  int black = 0;
  for (int y = h - 40; y < h - 4; ++y)
    for (int x = 4; x < 90; ++x)
      black += fray.pixel(x, y)[0] == 0 && fray.pixel(x, y)[1] == 0 && fray.pixel(x, y)[2] == 0;
  EXPECT_GT(black, 1000) << "the legend's black box";
  EXPECT_GT(whitePixels(fray, frayBox), 50) << "its caption and labels";
  EXPECT_GT(whitePixels(fray, {0, h - 75, w / 3, 20}), 20) << "the scale bar above it";
  if (test::envFlag("DTF_TEST_SAVE_IMAGES")) io::writePng((test::binaryDir() / "view_figure_fray.png").string(), fray);
}

TEST(ViewFigure, TheViewerRecordsSliceAndFaSweepsOfThePane) {
  DTF_GL_TEST_SETUP();
  const std::string phantom = (test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();
  const auto dir = test::scratchDir();
  test::ViewScene v("slice=axial");
  v.apply(session::LoadFile{phantom, "auto"});
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  session::RecordMovie sweep{(dir / "sweep/").string(), 4};
  sweep.kind = session::RecordMovie::Kind::Sweep;
  sweep.axis = "axial";
  v.apply(sweep);
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  session::RecordMovie fa{(dir / "fa/").string(), 3};
  fa.kind = session::RecordMovie::Kind::FaSweep;
  fa.faLo = 0.2;
  fa.faHi = 0.5;
  v.apply(fa);
  v.converge();
  ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
  auto frames = [](const std::filesystem::path& d) {
    std::vector<Image> out;
    for (int i = 0;; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.png", i);
      if (!std::filesystem::exists(d / name)) break;
      out.push_back(io::readPng((d / name).string()));
    }
    return out;
  };
  const auto s = frames(dir / "sweep"), f = frames(dir / "fa");
  ASSERT_EQ(s.size(), 4u);
  ASSERT_EQ(f.size(), 3u);
  // Each frame shows another slice / another isosurface: consecutive frames differ.
  auto differ = [](const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) n += std::abs(int(a.rgba[i]) - int(b.rgba[i])) > 30;
    return n;
  };
  for (std::size_t i = 1; i < s.size(); ++i) EXPECT_GT(differ(s[i - 1], s[i]), 500u) << i;
  for (std::size_t i = 1; i < f.size(); ++i) EXPECT_GT(differ(f[i - 1], f[i]), 200u) << i;
  EXPECT_EQ(v.state().recordStatus, "wrote 3 frames to " + (dir / "fa/").string());
}
