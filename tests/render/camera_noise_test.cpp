// SPDX-License-Identifier: GPL-3.0-or-later
// Pure C++ parts of render: view conventions of the camera, trackball maths, and the reaction-diffusion
// noise (seamless, deterministic per seed).
#include "support/test_env.h"

#include "io/model/error.h"
#include "render/camera.h"
#include "render/noise.h"

#include <cmath>

using namespace dtf::render;

namespace {
// Image-space x (NDC, right positive) and y (up positive) of a world point.
glm::dvec2 ndc(const Camera& c, const glm::dvec3& p) {
  glm::dvec4 q = c.projection(1.0) * c.view() * glm::dvec4(p, 1.0);
  return glm::dvec2(q) / q.w;
}
const glm::dvec3 kLo(-50, -60, -40), kHi(50, 60, 40);
const glm::dvec3 kRight(30, 0, 0), kAnterior(0, 30, 0), kSuperior(0, 0, 30);
} // namespace

TEST(Camera, StandardViewsFollowTheDocumentedConventions) {
  auto view = [](StandardView v, bool neuro = false) { return Camera::standard(v, kLo, kHi, 1.0, neuro); };
  // superior: patient's right on the image right, anterior up.
  EXPECT_GT(ndc(view(StandardView::Superior), kRight).x, 0.1);
  EXPECT_GT(ndc(view(StandardView::Superior), kAnterior).y, 0.1);
  // inferior: right on the image left, anterior up.
  EXPECT_LT(ndc(view(StandardView::Inferior), kRight).x, -0.1);
  EXPECT_GT(ndc(view(StandardView::Inferior), kAnterior).y, 0.1);
  // anterior / posterior: superior up; right on the left / right.
  EXPECT_LT(ndc(view(StandardView::Anterior), kRight).x, -0.1);
  EXPECT_GT(ndc(view(StandardView::Anterior), kSuperior).y, 0.1);
  EXPECT_GT(ndc(view(StandardView::Posterior), kRight).x, 0.1);
  // left: camera at the patient's left looking right: anterior on the image left. right: the opposite.
  Camera left = view(StandardView::Left);
  EXPECT_LT(left.eye.x, left.target.x);
  EXPECT_LT(ndc(left, kAnterior).x, -0.1);
  EXPECT_GT(ndc(left, kSuperior).y, 0.1);
  Camera right = view(StandardView::Right);
  EXPECT_GT(right.eye.x, right.target.x);
  EXPECT_GT(ndc(right, kAnterior).x, 0.1);
  // Radiological display convention by default: patient's right on the image left, anterior up (axial).
  EXPECT_LT(ndc(view(StandardView::Axial), kRight).x, -0.1);
  EXPECT_GT(ndc(view(StandardView::Axial), kAnterior).y, 0.1);
  EXPECT_LT(ndc(view(StandardView::Coronal), kRight).x, -0.1);
  EXPECT_GT(ndc(view(StandardView::Coronal), kSuperior).y, 0.1);
  EXPECT_LT(ndc(view(StandardView::Sagittal), kAnterior).x, -0.1);
  // Neurological flips left-right.
  EXPECT_GT(ndc(view(StandardView::Axial, true), kRight).x, 0.1);
  EXPECT_GT(ndc(view(StandardView::Coronal, true), kRight).x, 0.1);
  EXPECT_GT(ndc(view(StandardView::Sagittal, true), kAnterior).x, 0.1);
  EXPECT_EQ(parseView("coronal"), StandardView::Coronal);
  EXPECT_THROW(parseView("oblique"), dtf::UsageError);
}

TEST(Camera, FitKeepsTheBoxInsideTheViewport) {
  for (bool ortho : {true, false}) {
    Camera c = Camera::standard(StandardView::Anterior, kLo, kHi, 4.0 / 3.0, false, ortho);
    double maxAbs = 0;
    for (int i = 0; i < 8; ++i) {
      glm::dvec3 p((i & 1) ? kHi.x : kLo.x, (i & 2) ? kHi.y : kLo.y, (i & 4) ? kHi.z : kLo.z);
      glm::dvec4 q = c.projection(4.0 / 3.0) * c.view() * glm::dvec4(p, 1.0);
      glm::dvec3 n = glm::dvec3(q) / q.w;
      maxAbs = std::max({maxAbs, std::abs(n.x), std::abs(n.y)});
      EXPECT_GT(n.z, -1.0);
      EXPECT_LT(n.z, 1.0);
    }
    EXPECT_LT(maxAbs, 1.0);
    EXPECT_GT(maxAbs, 0.8); // and fills it
  }
}

TEST(Camera, TrackballRotatesAboutTheTargetAndKeepsTheDistance) {
  Camera c = Camera::standard(StandardView::Superior, kLo, kHi, 1.0);
  double dist = glm::length(c.eye - c.target);
  glm::dvec3 target = c.target;
  // Dragging right by a quarter of the sphere rotates the scene about the image's up axis.
  c.trackball({0.0, 0.0}, {0.5, 0.0});
  EXPECT_NEAR(glm::length(c.eye - c.target), dist, 1e-9 * dist);
  EXPECT_EQ(c.target, target);
  double expected = std::asin(0.5);
  glm::dvec3 f = c.forward();
  EXPECT_NEAR(std::acos(std::clamp(-f.z, -1.0, 1.0)), expected, 1e-9);
  // The scene point on the right edge moved towards the camera: the scene turned like the mouse.
  glm::dmat3 r = arcballRotation({0, 0}, {0.5, 0});
  glm::dvec3 moved = r * glm::dvec3(0, 0, 1);
  EXPECT_NEAR(moved.x, 0.5, 1e-12);
  EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
  EXPECT_EQ(arcballRotation({0.2, 0.1}, {0.2, 0.1}), glm::dmat3(1.0));
}

TEST(Noise, ReactionDiffusionIsDeterministicPerSeed) {
  NoiseOptions o;
  o.size = 64;
  o.iterations = 600;
  NoiseTile a = makeReactionDiffusion(o), b = makeReactionDiffusion(o);
  EXPECT_EQ(a.values, b.values);
  o.seed = 2;
  NoiseTile c = makeReactionDiffusion(o);
  EXPECT_NE(a.values, c.values);
  for (float v : a.values) {
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
  }
  EXPECT_EQ(cachedReactionDiffusion(o).get(), cachedReactionDiffusion(o).get());
}

TEST(Noise, ReactionDiffusionTileIsSeamless) {
  NoiseOptions o;
  o.size = 128;
  NoiseTile t = makeReactionDiffusion(o);
  const int n = t.size;
  // Mean |difference| between neighbouring columns/rows: across the wrap it must look like any interior
  // neighbour pair, and clearly smaller than between unrelated columns.
  auto colDiff = [&](int a, int b) {
    double s = 0;
    for (int y = 0; y < n; ++y) s += std::abs(t.at(a, y) - t.at(b, y));
    return s / n;
  };
  auto rowDiff = [&](int a, int b) {
    double s = 0;
    for (int x = 0; x < n; ++x) s += std::abs(t.at(x, a) - t.at(x, b));
    return s / n;
  };
  double interior = 0, far = 0;
  for (int i = 1; i < n - 1; ++i) {
    interior += 0.5 * (colDiff(i - 1, i) + rowDiff(i - 1, i));
    far += 0.5 * (colDiff(i, (i + n / 2) % n) + rowDiff(i, (i + n / 2) % n));
  }
  interior /= n - 2;
  far /= n - 2;
  double wrapX = colDiff(n - 1, 0), wrapY = rowDiff(n - 1, 0);
  EXPECT_LT(wrapX, 1.5 * interior);
  EXPECT_LT(wrapY, 1.5 * interior);
  EXPECT_LT(interior, 0.6 * far);
}
