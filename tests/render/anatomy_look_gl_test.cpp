// SPDX-License-Identifier: GPL-3.0-or-later
// The anatomy look and the data's smooth edge, measured in pixels: a background volume on another grid
// (rotated, coarser, shifted) shows through isotropic tissue at its world-space value, white matter keeps
// its DEC colour, the plain look covers isotropic tissue with the fabric, and the data's edge is drawn with
// partial coverage along a sub-voxel contour; the fabric along streamlines (--fabric-along) shows the anatomy
// away from them and the full fabric on them.
#include "io/formats/png_io.h"
#include "render/fabric_renderer.h"
#include "render/reference/scenes.h"
#include "support/gl_test.h"
#include "surfaces/analyses/tract_proximity.h"

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

// --fabric-along: the fabric only near streamlines (a proximity weight, surfaces/analyses/tract_proximity.h).
// A straight streamline across the white matter: away from it every pixel is the anatomy-only render's (the
// background, the fabric hidden by an FA floor above any FA), near it the full fabric render's.
TEST_F(AnatomyLook, TheFabricAlongStreamlinesShowsTheAnatomyAwayFromThemAndTheThreadsOnThem) {
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
  p.look = Look::Plain; // the fabric everywhere there is data, so the isotropic half shows it too
  const Image full = r.renderStill(cam, p);
  FabricParams none = p;
  none.faFloor = 2.0f; // no fabric anywhere: the anatomy alone
  const Image anatomy = r.renderStill(cam, none);

  // One streamline along y at x = 6, z = 0, from y = -20 to 20: it crosses nothing but white matter; a second
  // one along x at y = -12 from x = -20 to -8, in the isotropic half.
  Polylines lines;
  lines.offsets = {0};
  for (int i = 0; i <= 40; ++i)
    lines.points.emplace_back(6.0f, -20.0f + i, 0.0f);
  lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  for (int i = 0; i <= 12; ++i)
    lines.points.emplace_back(-20.0f + i, -12.0f, 0.0f);
  lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  surfaces::TractProximityOptions o;
  o.mm = 4.0;
  const surfaces::TractProximity near = surfaces::tractProximity(lines, o);
  ASSERT_EQ(near.voxelMm, 1.0);
  r.setAlong(&near.weight);
  const Image along = r.renderStill(cam, p);
  r.setAlong(nullptr);
  EXPECT_FALSE(r.hasAlong());
  for (const auto& [name, img] : {std::pair<const char*, const Image*>{"full.png", &full},
                                  {"anatomy.png", &anatomy},
                                  {"along.png", &along}})
    io::writePng((test::scratchDir() / name).string(), *img);

  const auto distance = [&](const glm::dvec3& w) {
    double d = 1e9;
    for (std::size_t l = 0; l + 1 < lines.offsets.size(); ++l) {
      const glm::dvec3 a(lines.points[lines.offsets[l]]), b(lines.points[lines.offsets[l + 1] - 1]);
      const double t = std::clamp(glm::dot(w - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
      d = std::min(d, glm::length(w - glm::mix(a, b, t)));
    }
    return d;
  };
  const auto differs = [](const std::uint8_t* a, const std::uint8_t* b) {
    return std::abs(a[0] - b[0]) > 1 || std::abs(a[1] - b[1]) > 1 || std::abs(a[2] - b[2]) > 1;
  };
  // Weight 0 beyond mm + 2.2 h and 1 within mm - 1.7 h (h = 1 mm), one more voxel either way for the
  // trilinear sample between voxel centres.
  int far = 0, farSame = 0, on = 0, onSame = 0, onFabric = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const glm::dvec3 w = worldOfPixel(r.frameView(), x, y);
      if (std::abs(w.x) > 28 || std::abs(w.y) > 28) continue;
      const double d = distance(w);
      if (d > o.mm + 3.3) {
        ++far;
        if (!differs(along.pixel(x, y), anatomy.pixel(x, y))) ++farSame;
      } else if (d < o.mm - 2.8) {
        ++on;
        if (!differs(along.pixel(x, y), full.pixel(x, y))) ++onSame;
        if (differs(full.pixel(x, y), anatomy.pixel(x, y))) ++onFabric;
      }
    }
  ASSERT_GT(far, 30000);
  ASSERT_GT(on, 1500);
  EXPECT_EQ(farSame, far); // the anatomy, exactly, away from the streamlines
  EXPECT_EQ(onSame, on);   // the threads of the full render, exactly, on them
  EXPECT_GT(onFabric, 0.8 * on) << onFabric << " of " << on; // where the fabric differs from the anatomy
}
