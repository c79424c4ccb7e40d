// SPDX-License-Identifier: GPL-3.0-or-later
// The anatomy look and the data's smooth edge, measured in pixels: a background volume on another grid
// (rotated, coarser, shifted) shows through isotropic tissue at its world-space value, white matter keeps
// its DEC colour, the plain look covers isotropic tissue with the fabric, and the data's edge is drawn with
// partial coverage along a sub-voxel contour.
#include "support/gl_test.h"

#include "render/fabric_renderer.h"
#include "render/reference/scenes.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

using namespace dtf;
using namespace dtf::render;

namespace {

class AnatomyLook : public GlTest {};

constexpr int kSize = 256;

// The background's value at a world point: smooth, so its trilinear resampling is close to it.
double backgroundAt(const glm::dvec3& p) {
  return 0.5 + 0.35 * std::sin(p.x / 9.0) * std::cos(p.y / 13.0);
}

// The world point of image pixel (x, y) (row 0 at the top) on the plane z = 0, from the viewport's matrix.
glm::dvec3 worldOfPixel(const FrameView& v, int x, int y) {
  const glm::dmat4 vp(v.viewProjViewport);
  const glm::dvec4 c0 = vp * glm::dvec4(0, 0, 0, 1);
  const glm::dvec4 ndc((x + 0.5) / kSize * 2 - 1, 1 - (y + 0.5) / kSize * 2, c0.z / c0.w, 1);
  const glm::dvec4 w = glm::inverse(vp) * ndc;
  return glm::dvec3(w) / w.w;
}

double saturation(const std::uint8_t* c) {
  const double mx = std::max({c[0], c[1], c[2]}), mn = std::min({c[0], c[1], c[2]});
  return mx > 0 ? (mx - mn) / mx : 0.0;
}

struct Scene {
  Mesh mesh = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8);
  Grid grid = reference::centredGrid(32, 2.0);
  TensorField field;
  ScalarVolume background;
  glm::dvec3 lo{-30, -30, -1}, hi{30, 30, 1};

  Scene() {
    // x < 0: isotropic (FA 0); x >= 0: along x (FA ~0.8).
    field = reference::constantField(grid, {1, 0, 0});
    const TensorField iso = reference::constantField(grid, {1, 0, 0}, 0.8e-3, 0.8e-3);
    for (int k = 0; k < 32; ++k)
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 16; ++i)
          field.at(i, j, k) = iso.at(i, j, k);
    // Another grid: 3.3 mm voxels, rotated 20 degrees about z and 25 degrees about x, shifted.
    glm::dmat4 a = glm::translate(glm::dmat4(1.0), glm::dvec3(-41.0, -37.0, -35.0));
    a = a * glm::rotate(glm::dmat4(1.0), glm::radians(20.0), glm::dvec3(0, 0, 1));
    a = a * glm::rotate(glm::dmat4(1.0), glm::radians(25.0), glm::dvec3(1, 0, 0));
    a = glm::translate(a, glm::dvec3(-6.0, -8.0, -10.0));
    a = a * glm::scale(glm::dmat4(1.0), glm::dvec3(3.3));
    background = ScalarVolume(Grid::fromAffine(glm::ivec3(36), a), 1);
    for (int k = 0; k < 36; ++k)
      for (int j = 0; j < 36; ++j)
        for (int i = 0; i < 36; ++i)
          background.data[background.grid.index(i, j, k)] =
              static_cast<float>(backgroundAt(background.grid.toWorld({i, j, k})));
  }
};

struct Counts {
  int isoMatch = 0, iso = 0, whiteRed = 0, white = 0;
};

Counts measure(const Image& img, const FrameView& view) {
  Counts n;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const glm::dvec3 p = worldOfPixel(view, x, y);
      if (std::abs(p.y) > 26) continue;
      const auto* c = img.pixel(x, y);
      if (p.x < -4 && p.x > -26) {
        ++n.iso;
        const double grey = (c[0] + c[1] + c[2]) / (3 * 255.0);
        if (std::abs(grey - backgroundAt(p)) < 0.04 && saturation(c) < 0.05) ++n.isoMatch;
      } else if (p.x > 4 && p.x < 26) {
        ++n.white;
        if (c[0] > 2 * std::max<int>(c[1], c[2])) ++n.whiteRed;
      }
    }
  return n;
}

} // namespace

TEST_F(AnatomyLook, ABackgroundOnAnotherGridShowsThroughIsotropicTissueAtItsWorldValue) {
  Scene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.setField(s.field);
  r.setBackground(&s.background, 0.0f, 1.0f);
  r.resize(kSize, kSize);
  const Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  p.lighting = false;
  p.silhouette = false;
  ASSERT_EQ(p.look, Look::Anatomy); // the default
  const Image anatomy = r.renderStill(cam, p);
  const Counts a = measure(anatomy, r.frameView());
  ASSERT_GT(a.iso, 5000);
  ASSERT_GT(a.white, 5000);
  // Isotropic tissue: the background's grey at each pixel's world point (trilinear on its own grid).
  EXPECT_GT(a.isoMatch, 0.97 * a.iso) << a.isoMatch << " of " << a.iso;
  // White matter: the fabric in its DEC colour (x: red).
  EXPECT_GT(a.whiteRed, 0.9 * a.white) << a.whiteRed << " of " << a.white;

  p.look = Look::Plain;
  const Image plain = r.renderStill(cam, p);
  const Counts b = measure(plain, r.frameView());
  // The paper's look: isotropic tissue carries the (grey) fabric, not the background.
  EXPECT_LT(b.isoMatch, 0.3 * b.iso) << b.isoMatch << " of " << b.iso;
  EXPECT_GT(b.whiteRed, 0.9 * b.white);
}

TEST_F(AnatomyLook, WithoutABackgroundVolumeFaIsBeneathAndTheOpacityFollowsTheRamp) {
  Scene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.setField(s.field);
  r.resize(kSize, kSize);
  const Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  p.lighting = false;
  p.silhouette = false;
  const Image img = r.renderStill(cam, p);
  int dark = 0, iso = 0;
  for (int y = 40; y < 216; ++y)
    for (int x = 0; x < kSize; ++x) {
      const glm::dvec3 w = worldOfPixel(r.frameView(), x, y);
      if (w.x < -4 && w.x > -26) {
        ++iso;
        const auto* c = img.pixel(x, y);
        if (std::max({c[0], c[1], c[2]}) <= 3) ++dark; // FA 0 beneath, no fabric
      }
    }
  ASSERT_GT(iso, 3000);
  EXPECT_GT(dark, 0.97 * iso);
  // A ramp that starts above the white matter's FA hides the fabric there too.
  p.opacityFaLow = 0.9f;
  p.opacityFaHigh = 0.95f;
  const Image hidden = r.renderStill(cam, p);
  int red = 0;
  for (int y = 40; y < 216; ++y)
    for (int x = 150; x < 230; ++x)
      if (hidden.pixel(x, y)[0] > 2 * std::max<int>(hidden.pixel(x, y)[1], 8)) ++red;
  EXPECT_EQ(red, 0);
}
