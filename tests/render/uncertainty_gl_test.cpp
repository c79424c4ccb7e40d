// SPDX-License-Identifier: GPL-3.0-or-later
// Uncertainty as fraying threads (shaders/common/fray.glsl): the projection's turned directions against the
// CPU reference (render/fray.h), and the whole pipeline on a constant field whose cone widens across the
// slice: the threads' coherence falls with the cone while their orientation stays the data's; without a
// cone map (or with a zero one) the field looks the same everywhere.
#include "io/model/tensor.h"
#include "render/fabric/projection_pass.h"
#include "render/fabric_renderer.h"
#include "render/fray.h"
#include "render/reference/scenes.h"
#include "support/gl_test.h"
#include "support/orientation_histogram.h"
#include "support/vector_texels.h"

#include <algorithm>
#include <cstring>
#include <functional>

using namespace dtf;
using namespace dtf::render;

namespace {

class Uncertainty : public GlTest {};

using dtf::test::readVectors;

Texture flatNoise() {
  NoiseTile tile;
  tile.size = 8;
  tile.values.assign(64, 0.5f);
  return uploadNoise(tile);
}

// A cone map on `grid`: f(world position) degrees.
ScalarVolume coneMap(const Grid& grid, const std::function<float(glm::dvec3)>& f) {
  ScalarVolume v(grid, 1);
  for (int k = 0; k < grid.dims.z; ++k)
    for (int j = 0; j < grid.dims.y; ++j)
      for (int i = 0; i < grid.dims.x; ++i)
        v.data[grid.index(i, j, k)] = f(grid.toWorld(glm::dvec3(i, j, k)));
  return v;
}

struct AxialScene {
  Mesh mesh = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8);
  Grid grid = reference::centredGrid(32, 2.0);
  glm::dvec3 lo{-30, -30, -1}, hi{30, 30, 1};
};

} // namespace

TEST(FrayReference, DrawsAreUniformSymmetricAndPerCell) {
  // The draw is constant inside a cell, differs between cells, and spreads over [-1, 1] with mean ~0.
  EXPECT_EQ(frayDraw({0.1f, 0.1f, 0.1f}, glm::vec3(0), 16, 16, 0),
            frayDraw({0.9f, 0.5f, 0.2f}, glm::vec3(0), 16, 16, 0));
  double sum = 0, sq = 0, lo = 1, hi = -1;
  int n = 0, differ = 0;
  for (int j = -50; j < 50; ++j)
    for (int i = -50; i < 50; ++i) {
      const float d = frayDraw({i + 0.5f, j + 0.5f, 0.5f}, glm::vec3(0), 1, 1, 0);
      ASSERT_GE(d, -1.0f);
      ASSERT_LE(d, 1.0f);
      sum += d;
      sq += d * d;
      lo = std::min(lo, double(d));
      hi = std::max(hi, double(d));
      differ += d != frayDraw({i + 1.5f, j + 0.5f, 0.5f}, glm::vec3(0), 1, 1, 0);
      ++n;
    }
  EXPECT_NEAR(sum / n, 0.0, 0.03);
  EXPECT_NEAR(sq / n, 1.0 / 3.0, 0.02); // variance of U(-1, 1)
  EXPECT_LT(lo, -0.99);
  EXPECT_GT(hi, 0.99);
  EXPECT_GT(differ, n * 99 / 100);
  EXPECT_NEAR(frayAngle({0.5f, 0.5f, 0.5f}, glm::vec3(0), 1, 1, 30, 2),
              frayDraw({0.5f, 0.5f, 0.5f}, glm::vec3(0), 1, 1, 0) * 2 * glm::radians(30.0f), 1e-6);
}

TEST_F(Uncertainty, ProjectedDirectionsTurnAsTheCpuReference) {
  constexpr int kW = 96, kH = 96;
  Mesh plane = reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 4);
  const Grid grid = reference::centredGrid(32, 2.0);
  const TensorField field = reference::constantField(grid, {1, 0, 0}, 1.7e-3, 0.3e-3);
  // Cone 35 degrees everywhere: trilinear filtering of a constant gives the constant.
  const ScalarVolume cone = coneMap(grid, [](glm::dvec3) { return 35.0f; });
  GpuMesh mesh;
  mesh.upload(plane);
  GpuTensorField gpuField;
  gpuField.upload(field);
  GpuScalarVolume gpuCone;
  gpuCone.upload(cone, 0.0f, 90.0f);
  Texture noise = flatNoise();
  Camera cam;
  cam.orthographic = true;
  cam.lookAt({0, 0, 80}, {0, 0, 0}, {0, 1, 0});
  cam.fit({-30, -30, -1}, {30, 30, 1}, 1.0);
  FrameView view = FrameView::make(cam, {kW, kH}, 4, {-30, -30, -1}, {30, 30, 1});
  ProjectionPass pass;
  ProjectionSettings ps;
  ps.lod = 20.0f;
  ps.noiseOrigin = glm::vec3(-31, -31, -1);
  ps.uncertainty = &gpuCone;
  ps.fray = 1.5f;
  ps.frayCells = 8.0f; // cells of 2.5 mm, ~4 pixels
  pass.run(mesh, gpuField, noise, view, ps);
  const auto vec = readVectors(pass.vectors());
  const auto surf = test::readTexture(pass.surface(), 4);

  const glm::dmat4 inv = glm::inverse(glm::dmat4(view.viewProj));
  auto unproject = [&](glm::dvec2 px) { // pixel -> point on z = 0
    const glm::dvec2 ndc = px / glm::dvec2(view.target) * 2.0 - 1.0;
    const glm::dvec4 a = inv * glm::dvec4(ndc, -1, 1), b = inv * glm::dvec4(ndc, 1, 1);
    const glm::dvec3 pa = glm::dvec3(a) / a.w, pb = glm::dvec3(b) / b.w;
    return pa + (-pa.z / (pb.z - pa.z)) * (pb - pa);
  };
  int checked = 0, turned = 0;
  double maxTurn = 0;
  for (int y = 0; y < view.target.y; ++y)
    for (int x = 0; x < view.target.x; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * view.target.x + x;
      if (surf[i * 4 + 3] < 0.5f) continue;
      const glm::dvec2 px(x + 0.5, y + 0.5);
      const glm::dvec3 world = unproject(px);
      // Skip pixels within 0.1 mm of a cell boundary: the GPU's world position carries rounding.
      const glm::dvec3 cell = (world - glm::dvec3(ps.noiseOrigin)) / double(ps.lod) * double(ps.frayCells);
      const glm::dvec3 f = cell - glm::floor(cell);
      if (std::min(std::min(f.x, 1 - f.x), std::min(f.y, 1 - f.y)) < 0.04) continue;
      const float angle = frayAngle(glm::vec3(world), ps.noiseOrigin, ps.lod, ps.frayCells, 35.0f, ps.fray);
      const glm::dvec3 expected(std::cos(angle), std::sin(angle), 0.0); // e1 = x turned about n = +z
      const glm::dvec2 iv(vec[i * 4], vec[i * 4 + 1]);
      const glm::dvec3 w = glm::normalize(unproject(px + 0.25 * iv) - world);
      EXPECT_GT(std::abs(glm::dot(w, expected)), 0.9995) << "pixel " << x << "," << y;
      // The second direction stays perpendicular to the first.
      const glm::dvec2 iv2(vec[i * 4 + 2], vec[i * 4 + 3]);
      const glm::dvec3 w2 = glm::normalize(unproject(px + 0.25 * iv2) - world);
      EXPECT_LT(std::abs(glm::dot(w2, expected)), 0.01);
      maxTurn = std::max(maxTurn, std::abs(double(angle)));
      turned += std::abs(angle) > glm::radians(5.0f);
      ++checked;
    }
  glUseProgram(0); // the pass's program is deleted with it; a later renderer's state restore must not see it
  EXPECT_GT(checked, 3000);
  EXPECT_GT(turned, checked / 2);
  EXPECT_GT(glm::degrees(maxTurn), 45.0); // up to 1.5 x 35 degrees
}

TEST_F(Uncertainty, ThreadsFrayAsTheConeWidensWhileTheirOrientationStaysTrue) {
  AxialScene s;
  FabricRenderer r;
  r.setMesh(s.mesh);
  r.resize(256, 256);
  r.setField(reference::constantField(s.grid, {1, 0, 0}));
  const Camera cam = Camera::standard(StandardView::Superior, s.lo, s.hi, 1.0);
  FabricParams p;
  // Seen from superior, image up = +y: the cone grows from 0 at the bottom to 80 degrees at the top.
  const ScalarVolume widening = coneMap(s.grid, [](glm::dvec3 w) {
    return static_cast<float>(std::clamp((w.y + 30.0) / 60.0, 0.0, 1.0) * 80.0);
  });
  const Image plain = r.renderStill(cam, p);
  const ScalarVolume zero = coneMap(s.grid, [](glm::dvec3) { return 0.0f; });
  r.setUncertainty(&zero);
  const Image zeroCone = r.renderStill(cam, p);
  EXPECT_EQ(zeroCone.rgba, plain.rgba) << "a zero cone must not change the image";
  r.setUncertainty(&widening);
  // Three cell layouts (cells of ~10, 8 and 6 pixels): one band holds a few hundred cells, whose turns'
  // mean moves the band's measured orientation by several degrees; over three layouts it averages out.
  std::vector<Image> frayed;
  for (double cells : {24.0, 31.0, 40.0}) {
    p.frayCells = cells;
    frayed.push_back(r.renderStill(cam, p));
  }
  r.setUncertainty(nullptr);

  // Four bands of rows 40..216 from bottom to top, cones growing from about 15 to 65 degrees. For turns drawn
  // uniformly in +-a the orientation coherence of ideal threads is sin(2a) / 2a: 0.93, 0.61, 0.30, 0.06 at
  // fray 1 before the breaks at cell boundaries lower it further.
  const int bands = 4, top = 40, bottom = 216;
  std::vector<double> cohPlain, cohFrayed;
  for (int b = 0; b < bands; ++b) {
    const int y1 = bottom - b * (bottom - top) / bands, y0 = y1 - (bottom - top) / bands;
    double cp = 0;
    const double op = test::dominantOrientation(plain, 40, y0, 216, y1, &cp);
    glm::dvec2 mean(0.0); // doubled-angle mean of the layouts' orientations
    double cf = 0;
    for (const Image& img : frayed) {
      double c = 0;
      const double o = glm::radians(test::dominantOrientation(img, 40, y0, 216, y1, &c));
      mean += glm::dvec2(std::cos(2 * o), std::sin(2 * o));
      cf += c / frayed.size();
      EXPECT_LT(test::orientationDiff(glm::degrees(o), 0.0), 15.0) << "band " << b;
    }
    const double of = glm::degrees(0.5 * std::atan2(mean.y, mean.x));
    std::printf(
        "band %d (rows %d..%d): coherence plain %.3f frayed %.3f, orientation plain %.1f frayed %.1f\n", b,
        y0, y1, cp, cf, op, of);
    cohPlain.push_back(cp);
    cohFrayed.push_back(cf);
    EXPECT_LT(test::orientationDiff(op, 0.0), 4.0);
    // The estimate's scatter grows as the coherence falls (widest band: ~0.27, about +-6 degrees).
    EXPECT_LT(test::orientationDiff(of, 0.0), 8.0)
        << "the mean direction must stay the data's (band " << b << ")";
  }
  const auto [lo, hi] = std::minmax_element(cohPlain.begin(), cohPlain.end());
  EXPECT_LT(*hi / *lo, 1.15) << "without uncertainty the field looks the same everywhere";
  for (int b = 1; b < bands; ++b)
    EXPECT_LT(cohFrayed[b], cohFrayed[b - 1]) << "coherence must fall as the cone widens (band " << b << ")";
  EXPECT_LT(cohFrayed[bands - 1], 0.5 * cohPlain[bands - 1]);
  EXPECT_GT(cohFrayed[0], 0.7 * cohPlain[0]);
}

TEST(FrayLegend, DrawsSwatchesAndLabelsInTheCorner) {
  Image img(256, 256);
  drawFrayLegend(img, 1.0f, 1);
  int lit = 0, litTop = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      if (img.pixel(x, y)[0] > 200) (y < 150 ? litTop : lit)++;
  EXPECT_GT(lit, 100);
  EXPECT_EQ(litTop, 0); // only at the bottom-left
  Image tiny(20, 20);
  drawFrayLegend(tiny, 1.0f, 1); // too small: draws nothing, no crash
  for (auto c : tiny.rgba)
    ASSERT_EQ(c, 0);
}

TEST_F(Uncertainty, EachFibrePopulationFraysByItsOwnCone) {
  // A crossing of an x bundle (the stronger, fibre 0, cone 0) and a y bundle (fibre 1, cone 30 degrees) on
  // an axial plane seen from above: x is the image's horizontal, y its vertical. The x slot's image
  // directions stay exactly horizontal; the y slot's turn within +-30 degrees of the vertical. With one
  // cone for every population (population 1's, 0) neither would turn; with the y cone for both, both would.
  const Grid grid = reference::centredGrid(24, 2.0);
  FibreSet set;
  set.grid = grid;
  set.maxFibres = 2;
  set.fibres.resize(grid.voxelCount() * 2);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
    set.fibres[v * 2] = {{1, 0, 0}, 0.6f};
    set.fibres[v * 2 + 1] = {{0, 1, 0}, 0.4f};
  }
  ScalarVolume cones(grid, 2);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
    cones.data[v * 2] = 0.0f;
    cones.data[v * 2 + 1] = 30.0f;
  }
  FabricRenderer r;
  r.setMesh(reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 40, 40, 4));
  r.setFibres(set);
  r.setUncertainty(&cones);
  r.resize(128, 128);
  FabricParams p;
  p.colour = ColourMode::Fibres;
  p.frayCells = 8;
  r.renderStill(Camera::standard(StandardView::Superior, {-20, -20, -1}, {20, 20, 1}, 1.0), p);
  const auto vec = readVectors(r.projection().vectors());
  const auto surf = test::readTexture(r.projection().surface(), 4);
  // Per covered pixel and slot: the angle of the image direction from the nearest image axis, and which.
  double xMax = 0, ySum = 0, yMax = 0;
  int xs = 0, ys = 0;
  for (std::size_t i = 0; i < surf.size() / 4; ++i) {
    if (surf[i * 4 + 3] < 0.5f) continue;
    for (int slot = 0; slot < 2; ++slot) {
      const double dx = vec[i * 4 + 2 * slot], dy = vec[i * 4 + 2 * slot + 1];
      if (std::hypot(dx, dy) < 0.5) continue;
      const double fromHorizontal = glm::degrees(std::atan(std::abs(dy) / std::max(std::abs(dx), 1e-9)));
      if (fromHorizontal < 45) {
        xMax = std::max(xMax, fromHorizontal);
        ++xs;
      } else {
        ySum += 90 - fromHorizontal;
        yMax = std::max(yMax, 90 - fromHorizontal);
        ++ys;
      }
    }
  }
  std::printf("x bundle: %d pixels, largest turn %.2f deg; y bundle: %d pixels, mean turn %.2f, largest %.2f\n", xs,
              xMax, ys, ySum / std::max(ys, 1), yMax);
  ASSERT_GT(xs, 5000);
  ASSERT_GT(ys, 5000);
  EXPECT_LT(xMax, 1.0);
  EXPECT_GT(ySum / ys, 8.0); // |U(-1, 1)| x 30 degrees: 15 on average
  EXPECT_LT(yMax, 31.0);
  // The same cones given in the other fibre order follow their fibres (the set's order is what counts).
  ScalarVolume swapped(grid, 2);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
    swapped.data[v * 2] = 30.0f;
    swapped.data[v * 2 + 1] = 0.0f;
  }
  r.setUncertainty(&swapped);
  r.renderStill(Camera::standard(StandardView::Superior, {-20, -20, -1}, {20, 20, 1}, 1.0), p);
  const auto vec2 = readVectors(r.projection().vectors());
  double xTurn = 0, yTurn = 0;
  for (std::size_t i = 0; i < surf.size() / 4; ++i) {
    if (surf[i * 4 + 3] < 0.5f) continue;
    for (int slot = 0; slot < 2; ++slot) {
      const double dx = vec2[i * 4 + 2 * slot], dy = vec2[i * 4 + 2 * slot + 1];
      if (std::hypot(dx, dy) < 0.5) continue;
      const double a = glm::degrees(std::atan(std::abs(dy) / std::max(std::abs(dx), 1e-9)));
      (a < 45 ? xTurn : yTurn) = std::max(a < 45 ? xTurn : yTurn, a < 45 ? a : 90 - a);
    }
  }
  EXPECT_GT(xTurn, 20.0);
  EXPECT_LT(yTurn, 1.0);
}
