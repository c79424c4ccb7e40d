// SPDX-License-Identifier: GPL-3.0-or-later
// Analytic phantoms against closed forms: the Bretzel5 derivatives against finite differences, the
// sphere's curvature tensor, the constant and crossing directions, and the brain phantom's bundle colours.
#include "io/model/error.h"
#include "io/model/tensor.h"
#include "io/phantoms.h"

#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace dtf;

namespace {
constexpr double kPi = 3.14159265358979323846;

// The voxel nearest a world position on an axis-aligned RAS grid.
glm::ivec3 voxelAt(const Grid& g, const glm::dvec3& world) {
  glm::dvec3 v = g.toVoxel(world);
  return {static_cast<int>(std::lround(v.x)), static_cast<int>(std::lround(v.y)),
          static_cast<int>(std::lround(v.z))};
}

glm::dvec3 principal(const TensorField& f, const glm::ivec3& v) {
  return eigenDecompose(f.at(v.x, v.y, v.z)).vectors[0];
}
} // namespace

TEST(Phantom, Bretzel5DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> xy(-2.2, 2.2), z(-1, 1);
  const double h = 1e-5;
  for (int n = 0; n < 200; ++n) {
    glm::dvec3 p(xy(rng), xy(rng), z(rng));
    io::Bretzel5Value v = io::bretzel5(p);
    double a = p.x * p.x + 0.25 * p.y * p.y - 1, b = 0.25 * p.x * p.x + p.y * p.y - 1;
    EXPECT_NEAR(v.f, a * a * b * b + p.z * p.z - 0.1, 1e-12);
    for (int i = 0; i < 3; ++i) {
      glm::dvec3 e(0.0);
      e[i] = h;
      io::Bretzel5Value plus = io::bretzel5(p + e), minus = io::bretzel5(p - e);
      double scale = 1 + std::abs(v.gradient[i]);
      EXPECT_NEAR((plus.f - minus.f) / (2 * h), v.gradient[i], 1e-6 * scale) << "df/dx" << i;
      // Column i of the Hessian is the derivative of the gradient along axis i.
      for (int j = 0; j < 3; ++j) {
        double fd = (plus.gradient[j] - minus.gradient[j]) / (2 * h);
        EXPECT_NEAR(fd, v.hessian[i][j], 1e-6 * (1 + std::abs(v.hessian[i][j]))) << "H" << i << j;
      }
      EXPECT_DOUBLE_EQ(v.hessian[i][(i + 1) % 3], v.hessian[(i + 1) % 3][i]);
    }
  }
}

TEST(Phantom, Bretzel5FieldIsTheHessianInWorldUnits) {
  io::PhantomOptions o;
  o.size = 45;
  o.spacing = 0.5;
  io::Phantom p = io::makePhantom("bretzel5", o);
  const Grid& g = p.tensors.grid;
  const double scale = (o.size - 1) * o.spacing / 4.4; // mm per function unit: x spans [-2.2, 2.2]
  glm::dvec3 lo, hi;
  g.worldBounds(lo, hi);
  EXPECT_NEAR(hi.x / scale, 2.2, 1e-9);
  EXPECT_NEAR(hi.z / scale, 1.0, 0.1);
  bool negative = false, positive = false;
  for (int k = 0; k < g.dims.z; k += 3)
    for (int j = 0; j < g.dims.y; j += 5)
      for (int i = 0; i < g.dims.x; i += 5) {
        glm::dvec3 w = g.toWorld(glm::dvec3(i, j, k));
        io::Bretzel5Value v = io::bretzel5(w / scale);
        glm::dmat3 expected = v.hessian / (scale * scale);
        SymTensor t = p.tensors.at(i, j, k);
        glm::dmat3 got = t.toMat();
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(got[c][r], expected[c][r], 1e-6 * (1 + std::abs(expected[c][r])));
        EXPECT_NEAR(p.scalar.at(i, j, k), v.f, 1e-5 * (1 + std::abs(v.f)));
        negative = negative || v.f < 0;
        positive = positive || v.f > 0;
      }
  EXPECT_TRUE(negative && positive); // the isosurface f = 0 lies inside the grid
  EXPECT_EQ(p.isovalue, 0.0);
}

TEST(Phantom, SphereIsTheHessianOfTheDistance) {
  io::PhantomOptions o;
  o.size = 33; // odd: one voxel sits at the centre
  io::Phantom p = io::makePhantom("sphere", o);
  const Grid& g = p.tensors.grid;
  EXPECT_NEAR(p.isovalue, 0.35 * 32, 1e-12);
  EXPECT_FALSE(p.tensors.valid[g.index(16, 16, 16)]); // undefined at r = 0
  glm::dvec3 x = g.toWorld(glm::dvec3(25, 10, 20));
  double r = glm::length(x);
  EXPECT_NEAR(p.scalar.at(25, 10, 20), r, 1e-4);
  EigenSystem e = eigenDecompose(p.tensors.at(25, 10, 20));
  EXPECT_NEAR(e.values[0], 1 / r, 1e-6);
  EXPECT_NEAR(e.values[1], 1 / r, 1e-6);
  EXPECT_NEAR(e.values[2], 0, 1e-6);
  EXPECT_NEAR(std::abs(glm::dot(e.vectors[2], x / r)), 1, 1e-5); // zero curvature along the radius
}

TEST(Phantom, ConstantPrincipalDirectionIsTheRequestedAngle) {
  for (double angle : {0.0, 30.0, 90.0, 135.0})
    for (double elevation : {0.0, 25.0, -60.0}) {
      io::PhantomOptions o;
      o.size = 8;
      o.angleDeg = angle;
      o.elevationDeg = elevation;
      io::Phantom p = io::makePhantom("constant", o);
      double az = angle * kPi / 180, el = elevation * kPi / 180;
      glm::dvec3 want(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      EigenSystem e = eigenDecompose(p.tensors.at(3, 4, 5));
      EXPECT_NEAR(std::abs(glm::dot(e.vectors[0], want)), 1.0, 1e-6) << angle << " " << elevation;
      EXPECT_NEAR(e.values[0], 1.7e-3, 1e-9);
      EXPECT_NEAR(e.values[1], 0.3e-3, 1e-9);
      EXPECT_NEAR(e.values[2], 0.3e-3, 1e-9);
      EXPECT_NEAR(p.scalar.at(1, 2, 3), 0.7990, 1e-3); // FA of (1.7, 0.3, 0.3)
    }
}

TEST(Phantom, CrossingSumsTheBundlesWhereTheyOverlap) {
  io::PhantomOptions o;
  o.size = 41;
  o.crossingDeg = 60;
  io::Phantom p = io::makePhantom("crossing", o);
  const Grid& g = p.tensors.grid;
  // Centre: both bundles, T1 + T2 with directions at -30 and +30 degrees: the sum's principal axis is +x.
  EigenSystem c = eigenDecompose(p.tensors.at(20, 20, 20));
  EXPECT_NEAR(std::abs(c.vectors[0].x), 1.0, 1e-6);
  EXPECT_NEAR(c.values[0] + c.values[1] + c.values[2], 2 * (1.7e-3 + 0.6e-3), 1e-8);
  // Far along bundle 2 (+30 degrees) only it is present.
  glm::dvec3 d2(std::cos(kPi / 6), std::sin(kPi / 6), 0);
  glm::ivec3 v = voxelAt(g, 16.0 * d2);
  EXPECT_NEAR(std::abs(glm::dot(principal(p.tensors, v), d2)), 1.0, 1e-6);
  EXPECT_NEAR(p.scalar.at(v.x, v.y, v.z), 0.7990, 1e-3);
  // Outside both bands: no data.
  EXPECT_FALSE(p.tensors.valid[g.index(20, 39, 20)]);
}

TEST(Phantom, BrainBundlesHaveTheirAnatomicalDirections) {
  io::PhantomOptions o;
  o.size = 48;
  o.spacing = 2.5;
  io::Phantom p = io::makePhantom("brain", o);
  const Grid& g = p.tensors.grid;
  const double ext = (o.size - 1) * o.spacing;
  EXPECT_EQ(g.orientationCode(), "RAS");
  glm::dvec3 lo, hi;
  g.worldBounds(lo, hi);
  EXPECT_NEAR(lo.x + hi.x, 0, 1e-9); // centred at the origin
  struct Probe {
    glm::dvec3 unit; // position / extent
    int axis;
    const char* what;
  } probes[] = {{{0.0, 0.0, 0.04}, 0, "corpus callosum (left-right)"},
                {{-0.2, 0.1, 0.0}, 0, "corpus callosum in the middle axial slice"},
                {{0.208, -0.22, -0.15}, 2, "corticospinal tract (superior-inferior)"},
                {{-0.22, -0.22, 0.0}, 2, "corticospinal tract in the middle axial slice"},
                {{-0.07, 0.0, 0.11}, 1, "cingulum over the callosum (anterior-posterior)"},
                {{0.07, -0.28, 0.0}, 1, "cingulum in the middle axial slice"}};
  for (const auto& pr : probes) {
    glm::ivec3 v = voxelAt(g, pr.unit * ext);
    ASSERT_TRUE(p.tensors.valid[g.index(v.x, v.y, v.z)]) << pr.what;
    EXPECT_GT(std::abs(principal(p.tensors, v)[pr.axis]), 0.9) << pr.what;
    EXPECT_GT(p.scalar.at(v.x, v.y, v.z), 0.7) << pr.what;
  }
  // Isotropic tissue, CSF rim, empty background.
  glm::ivec3 tissue = voxelAt(g, glm::dvec3(-0.2, 0.2, -0.1) * ext);
  EigenSystem t = eigenDecompose(p.tensors.at(tissue.x, tissue.y, tissue.z));
  EXPECT_NEAR(t.values[0], 1e-3, 1e-9);
  EXPECT_NEAR(t.values[2], 1e-3, 1e-9);
  glm::ivec3 rim = voxelAt(g, glm::dvec3(0.0, 0.0, 0.38) * ext);
  EXPECT_NEAR(computeMetrics(eigenDecompose(p.tensors.at(rim.x, rim.y, rim.z))).md, 3e-3, 1e-9);
  EXPECT_FALSE(p.tensors.valid[g.index(0, 0, 0)]);
}

TEST(Phantom, BadNamesAndSizesAreUsageErrors) {
  EXPECT_THROW(io::makePhantom("torus"), UsageError);
  io::PhantomOptions o;
  o.size = 2;
  EXPECT_THROW(io::makePhantom("sphere", o), UsageError);
  o.size = 8;
  o.spacing = -1;
  EXPECT_THROW(io::makePhantom("sphere", o), UsageError);
  EXPECT_EQ(io::phantomNames().size(), 5u);
  for (const auto& n : io::phantomNames()) {
    io::PhantomOptions small;
    small.size = 8;
    EXPECT_NO_THROW(io::makePhantom(n, small)) << n;
  }
}
