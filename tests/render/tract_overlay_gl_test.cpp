// SPDX-License-Identifier: GPL-3.0-or-later
// The tract overlay (render/tract_renderer.h) over the fabric: depth-correct against the opaque surface
// (the composite's gl_FragDepth), DEC colour by tangent, and the slab clip.
#include "support/gl_test.h"

#include "render/fabric_renderer.h"
#include "render/reference/scenes.h"
#include "render/tract_renderer.h"

#include <algorithm>

using namespace dtf;
using namespace dtf::render;

namespace {

class TractOverlay : public GlTest {};

constexpr int kSize = 192;

// An axial plane z = 0 of 60 x 60 mm carrying a constant field along y (green fabric), a camera fitted to a
// 60 mm cube (so tracts off the plane stay inside the clip volume), and the fabric rendered once.
struct Scene {
  Mesh mesh = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8);
  FabricRenderer fabric;
  TractRenderer tracts;
  Camera camera;
  Image plain;

  explicit Scene(StandardView v) {
    fabric.setMesh(mesh);
    fabric.setField(reference::constantField(reference::centredGrid(32, 2.0), {0, 1, 0}));
    fabric.resize(kSize, kSize);
    camera = Camera::standard(v, {-30, -30, -30}, {30, 30, 30}, 1.0);
    plain = fabric.renderStill(camera, FabricParams{});
  }
  Image overlay(const Polylines& lines, const TractStyle& style = {}) {
    fabric.renderStill(camera, FabricParams{});
    tracts.setTracts(lines);
    glBindFramebuffer(GL_FRAMEBUFFER, fabric.output().id());
    tracts.draw(fabric.frameView(), style);
    return fabric.readback();
  }
  // Image pixel (row 0 at the top) of a world point.
  glm::ivec2 pixel(const glm::vec3& p) const {
    glm::vec4 c = fabric.frameView().viewProjViewport * glm::vec4(p, 1.0f);
    return {static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kSize),
            static_cast<int>((0.5f - c.y / c.w * 0.5f) * kSize)};
  }
};

Polylines line(const glm::vec3& a, const glm::vec3& b, int n = 41) {
  Polylines l;
  l.offsets = {0};
  for (int i = 0; i < n; ++i) l.points.push_back(a + (b - a) * (float(i) / float(n - 1)));
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  return l;
}

bool samePixel(const Image& a, const Image& b, glm::ivec2 p) {
  return std::equal(a.pixel(p.x, p.y), a.pixel(p.x, p.y) + 4, b.pixel(p.x, p.y));
}

} // namespace

TEST_F(TractOverlay, TheOpaqueSurfaceHidesTheHalfBelowItSeenFromSuperior) {
  Scene s(StandardView::Superior);
  // Rises from 5 mm below the plane (x < 0) to 5 mm above it (x > 0).
  Image img = s.overlay(line({-25, 0, -5}, {25, 0, 5}));
  int hiddenSame = 0, visibleRed = 0, samples = 0;
  for (float x = -22; x <= -3; x += 1.0f) {
    glm::ivec2 p = s.pixel({x, 0, x / 5});
    hiddenSame += samePixel(img, s.plain, p);
    ++samples;
  }
  EXPECT_EQ(hiddenSame, samples) << "the tract below the surface showed through";
  samples = 0;
  for (float x = 3; x <= 22; x += 1.0f) {
    glm::ivec2 p = s.pixel({x, 0, x / 5});
    const auto* c = img.pixel(p.x, p.y);
    visibleRed += c[0] > 100 && c[0] > 2 * c[1] && c[0] > 2 * c[2];
    ++samples;
  }
  EXPECT_EQ(visibleRed, samples) << "the tract above the surface is not drawn in red";
}

TEST_F(TractOverlay, TangentAlongXIsRedAndAlongZIsBlue) {
  {
    Scene s(StandardView::Superior);
    Image img = s.overlay(line({-20, 10, 3}, {20, 10, 3}));
    glm::ivec2 p = s.pixel({0, 10, 3});
    const auto* c = img.pixel(p.x, p.y);
    EXPECT_GT(c[0], 150);
    EXPECT_LT(c[1], 10);
    EXPECT_LT(c[2], 10);
  }
  {
    // From anterior the plane is seen edge on; the tract stands in front of its anterior edge (y = 30).
    Scene s(StandardView::Anterior);
    Image img = s.overlay(line({10, 35, -20}, {10, 35, 20}));
    glm::ivec2 p = s.pixel({10, 35, 10});
    const auto* c = img.pixel(p.x, p.y);
    EXPECT_GT(c[2], 150);
    EXPECT_LT(c[0], 10);
    EXPECT_LT(c[1], 10);
  }
}

TEST_F(TractOverlay, SlabKeepsOnlyWhatLiesNearThePlane) {
  Scene s(StandardView::Superior);
  TractStyle style;
  style.plane = {0, 0, 1, 0};
  style.slabMm = 2.0f;
  // Two tracts above the surface: at z = 1 (inside the slab) and z = 4 (outside).
  Polylines both = line({-20, -10, 1}, {20, -10, 1});
  Polylines far = line({-20, 10, 4}, {20, 10, 4});
  both.points.insert(both.points.end(), far.points.begin(), far.points.end());
  both.offsets.push_back(static_cast<std::uint32_t>(both.points.size()));
  Image img = s.overlay(both, style);
  EXPECT_FALSE(samePixel(img, s.plain, s.pixel({0, -10, 1})));
  EXPECT_TRUE(samePixel(img, s.plain, s.pixel({0, 10, 4})));
  EXPECT_EQ(s.tracts.lineCount(), 2u);
}

TEST_F(TractOverlay, DrawIsDeterministic) {
  Scene s(StandardView::Superior);
  Polylines l = line({-25, -25, 2}, {25, 20, 3}, 200);
  Image a = s.overlay(l), b = s.overlay(l);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_NE(a.rgba, s.plain.rgba);
}

TEST_F(TractOverlay, TractsLyingInTheSurfaceStayVisible) {
  // TractStyle::depthBiasMm pulls the tube towards the viewer, so a tract in the slice plane is not lost
  // to z-fighting with the fabric's depth.
  Scene s(StandardView::Superior);
  Image img = s.overlay(line({-20, 5, 0}, {20, 5, 0}));
  int red = 0, samples = 0;
  for (float x = -18; x <= 18; x += 2.0f, ++samples) {
    glm::ivec2 p = s.pixel({x, 5, 0});
    const auto* c = img.pixel(p.x, p.y);
    red += c[0] > 150 && c[1] < 10 && c[2] < 10;
  }
  EXPECT_EQ(red, samples);
}
