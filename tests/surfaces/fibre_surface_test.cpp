// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre-following stream surfaces and the |e1 . n| quality figure on an analytic arch field.
#include "io/model/error.h"
#include "surfaces/fibre_surface.h"
#include "surfaces/slices.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dtf;

namespace {
// Fibres on circles about the y axis (an arch in every coronal plane): e1 = tangent (-z, 0, x)/r.
TensorField archField(int n) {
  glm::dmat4 a(1.0);
  a[3] = glm::dvec4(-(n - 1) / 2.0, -(n - 1) / 2.0, -(n - 1) / 2.0, 1.0);
  TensorField f = makeTensorField(Grid::fromAffine({n, n, n}, a));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        glm::dvec3 p = f.grid.toWorld({i, j, k});
        double r = std::hypot(p.x, p.z);
        if (r < 4) continue;
        glm::dvec3 e1(-p.z / r, 0, p.x / r);
        glm::dmat3 d = 3e-4 * glm::dmat3(1.0) + 1.4e-3 * glm::outerProduct(e1, e1);
        f.at(i, j, k) = SymTensor::fromMat(d);
        f.valid[f.grid.index(i, j, k)] = 1;
      }
  return f;
}
} // namespace

TEST(FibreSurface, StreamSurfaceContainsTheFibresAndBeatsTheFlatSlice) {
  TensorField f = archField(41);
  // Seed line along y at radius 12 in the axial plane z = 0, where the fibres run superior-inferior.
  surfaces::FibreSurfaceOptions o;
  o.maxLengthMm = 15;
  Mesh s = surfaces::fibreSurfaceFromLine(f, {12, -10, 0}, {12, 10, 0}, o);
  ASSERT_GT(s.triangleCount(), 200u);
  // Every vertex stays on the cylinder r = 12 (RK4 on a circle drifts little).
  double maxErr = 0;
  for (const auto& p : s.positions) maxErr = std::max(maxErr, std::abs(std::hypot(p.x, p.z) - 12.0));
  EXPECT_LT(maxErr, 0.05);
  double w = 0;
  const double fibre = surfaces::fibreCrossingScore(s, f, &w);
  EXPECT_GT(w, 0);
  EXPECT_LT(fibre, 0.05);
  // The axial slice through the seed line: fibres cross it almost at right angles near x = 12.
  Grid g = f.grid;
  Mesh slice = surfaces::makeSlice(g, surfaces::SliceAxis::Axial, 20);
  const double flat = surfaces::fibreCrossingScore(slice, f);
  EXPECT_GT(flat, 0.5);
}

TEST(FibreSurface, BadSeedsAreReported) {
  TensorField f = archField(21);
  EXPECT_THROW(surfaces::fibreSurfaceFromLine(f, {100, 0, 0}, {120, 0, 0}), InputError);
  EXPECT_THROW(surfaces::fibreSurfaceFromLine(f, {1, 1, 1}, {1, 1, 1}), UsageError);
  EXPECT_THROW(surfaces::fibreSurfaceFromLine(f, {0, -1, 0}, {0, 1, 0}), InputError); // r < 4: no data
}
