// SPDX-License-Identifier: GPL-3.0-or-later
// Eigen-solver and metrics against closed forms.
#include "io/model/grid.h"
#include "io/model/tensor.h"
#include "io/model/tensor_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace dtf;

namespace {
glm::dmat3 fromEigen(const glm::dvec3& l, const glm::dmat3& r) {
  return r * glm::dmat3(l.x, 0, 0, 0, l.y, 0, 0, 0, l.z) * glm::transpose(r);
}
glm::dmat3 randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  glm::dvec3 a(n(rng), n(rng), n(rng)), b(n(rng), n(rng), n(rng));
  a = glm::normalize(a);
  b = glm::normalize(b - glm::dot(a, b) * a);
  return glm::dmat3(a, b, glm::cross(a, b));
}
void expectDecomposition(const glm::dmat3& m, const EigenSystem& e, double tol) {
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(glm::length(e.vectors[i]), 1.0, 1e-9);
    glm::dvec3 residual = m * e.vectors[i] - e.values[i] * e.vectors[i];
    EXPECT_LT(glm::length(residual), tol) << "eigenpair " << i;
    for (int j = i + 1; j < 3; ++j) EXPECT_NEAR(glm::dot(e.vectors[i], e.vectors[j]), 0.0, 1e-9);
  }
  EXPECT_GE(e.values[0], e.values[1]);
  EXPECT_GE(e.values[1], e.values[2]);
}
} // namespace

TEST(Eigen, DiagonalTensor) {
  EigenSystem e = eigenDecompose(glm::dmat3(1e-3, 0, 0, 0, 3e-3, 0, 0, 0, 2e-3));
  EXPECT_NEAR(e.values[0], 3e-3, 1e-15);
  EXPECT_NEAR(e.values[1], 2e-3, 1e-15);
  EXPECT_NEAR(e.values[2], 1e-3, 1e-15);
  EXPECT_NEAR(std::abs(e.vectors[0].y), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(e.vectors[1].z), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(e.vectors[2].x), 1.0, 1e-12);
}

TEST(Eigen, ZeroAndIsotropicAndNaN) {
  for (double s : {0.0, 7e-4}) {
    EigenSystem e = eigenDecompose(glm::dmat3(s));
    EXPECT_EQ(e.values, glm::dvec3(s));
    expectDecomposition(glm::dmat3(s), e, 1e-15);
  }
  glm::dmat3 bad(1.0);
  bad[0][0] = std::nan("");
  EigenSystem e = eigenDecompose(bad);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(glm::length(e.vectors[i])));
}

TEST(Eigen, RandomRotationsWithRepeatedEigenvalues) {
  std::mt19937 rng(42);
  const glm::dvec3 spectra[] = {{1.7e-3, 3e-4, 2e-4}, {1e-3, 1e-3, 2e-4}, {1e-3, 3e-4, 3e-4},
                                {2e-3, 1e-3, -5e-4}, {1e-3, 1e-3 * (1 + 1e-9), 1e-3}};
  for (const auto& l : spectra) {
    for (int trial = 0; trial < 200; ++trial) {
      glm::dmat3 r = randomRotation(rng);
      glm::dmat3 m = fromEigen(l, r);
      EigenSystem e = eigenDecompose(m);
      // The trigonometric solver loses about half the digits at a double root (error ~ sqrt(eps) * |D|).
      EXPECT_NEAR(e.values[0], l[0], 1e-10);
      EXPECT_NEAR(e.values[1], l[1], 1e-10);
      EXPECT_NEAR(e.values[2], l[2], 1e-10);
      expectDecomposition(m, e, 1e-9);
      if (l[0] - l[1] > 1e-4) {
        EXPECT_NEAR(std::abs(glm::dot(e.vectors[0], r[0])), 1.0, 1e-8);
      }
      if (l[1] - l[2] > 1e-4 && l[0] - l[1] > 1e-4) {
        EXPECT_NEAR(std::abs(glm::dot(e.vectors[1], r[1])), 1.0, 1e-8);
      }
    }
  }
}

TEST(Metrics, ClosedForms) {
  // Prolate tensor (l, m, m): FA = |l - m| / sqrt(l^2 + 2 m^2).
  EigenSystem e;
  e.values = {1.7e-3, 3e-4, 3e-4};
  TensorMetrics t = computeMetrics(e);
  EXPECT_NEAR(t.fa, 1.4e-3 / std::sqrt(1.7e-3 * 1.7e-3 + 2 * 9e-8), 1e-12);
  EXPECT_NEAR(t.md, 7.6666666666e-4, 1e-12);
  EXPECT_DOUBLE_EQ(t.ad, 1.7e-3);
  EXPECT_NEAR(t.rd, 3e-4, 1e-15);
  EXPECT_NEAR(t.mode, 1.0, 1e-9); // linear
  e.values = {1e-3, 1e-3, 2e-4};
  EXPECT_NEAR(computeMetrics(e).mode, -1.0, 1e-9); // planar
  e.values = {1e-3, 1e-3, 1e-3};
  t = computeMetrics(e);
  EXPECT_EQ(t.fa, 0.0);
  EXPECT_EQ(t.mode, 0.0);
  e.values = {1.0, 0.0, 0.0};
  EXPECT_NEAR(computeMetrics(e).fa, 1.0, 1e-12);
  e.values = {0, 0, 0};
  EXPECT_EQ(computeMetrics(e).fa, 0.0);
}

TEST(Metrics, InvariantFaEqualsEigenvalueFa) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1e-3, 3e-3);
  for (int trial = 0; trial < 500; ++trial) {
    glm::dvec3 l(u(rng), u(rng), u(rng));
    SymTensor t = SymTensor::fromMat(fromEigen(l, randomRotation(rng)));
    EXPECT_NEAR(fractionalAnisotropy(t), fractionalAnisotropy(eigenDecompose(t).values), 1e-5);
  }
  EXPECT_EQ(fractionalAnisotropy(SymTensor{}), 0.0);
}

TEST(Metrics, DecColourFollowsPrincipalDirection) {
  EigenSystem e = eigenDecompose(glm::dmat3(1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 2e-3)); // along z
  glm::dvec3 c = decColor(e, 0.8);
  EXPECT_NEAR(c.z, 0.8, 1e-12);
  EXPECT_NEAR(c.x, 0.0, 1e-12);
  EXPECT_NEAR(c.y, 0.0, 1e-12);
  EXPECT_NEAR(decColor(e, 1.3).z, 1.0, 1e-12); // FSL-style FA > 1 is clamped
}

TEST(Grid, OrientationCodesAndRotation) {
  glm::dmat4 las(1.0);
  las[0][0] = -3;
  las[1][1] = 3;
  las[2][2] = 3;
  las[3] = glm::dvec4(108, -98.279, -23.396, 1);
  Grid g = Grid::fromAffine({72, 72, 39}, las);
  EXPECT_EQ(g.orientationCode(), "LAS");
  EXPECT_EQ(g.spacing, glm::dvec3(3.0));
  glm::dmat3 r = g.rotation();
  EXPECT_NEAR(r[0][0], -1.0, 1e-12);
  EXPECT_NEAR(r[1][1], 1.0, 1e-12);
  glm::dvec3 w = g.toWorld({33, 42, 22});
  EXPECT_NEAR(w.x, 108 - 99, 1e-9);
  glm::dvec3 back = g.toVoxel(w);
  EXPECT_NEAR(back.y, 42, 1e-9);
  // Rotating an x-y shear from LAS voxel frame to world flips the sign of xy and xz.
  SymTensor t{1, 0.1f, 0.2f, 1, 0.3f, 1};
  SymTensor wt = rotateTensor(t, r);
  EXPECT_FLOAT_EQ(wt.xy, -0.1f);
  EXPECT_FLOAT_EQ(wt.xz, -0.2f);
  EXPECT_FLOAT_EQ(wt.yz, 0.3f);
}

TEST(TensorField, TrilinearInterpolatesComponents) {
  Grid g = Grid::fromAffine({2, 1, 1}, glm::dmat4(1.0));
  TensorField f = makeTensorField(g);
  f.at(0, 0, 0) = SymTensor{1, 0, 0, 0, 0, 0};
  f.at(1, 0, 0) = SymTensor{0, 0, 0, 1, 0, 0};
  SymTensor mid = f.sample({0.5, 0, 0});
  EXPECT_FLOAT_EQ(mid.xx, 0.5f);
  EXPECT_FLOAT_EQ(mid.yy, 0.5f);
  EXPECT_TRUE(f.sample({-0.1, 0, 0}).isZero());
}
