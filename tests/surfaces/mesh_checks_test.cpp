// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL-backed mesh checks: self-intersections, repair, remeshing and AABB distances.
#include "io/model/error.h"
#include "surfaces/isosurface.h"
#include "surfaces/mesh_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace dtf;

namespace {
Mesh sphere(double radius, int n) {
  glm::dmat4 a(1.0);
  a[3] = glm::dvec4(-(n - 1) / 2.0, -(n - 1) / 2.0, -(n - 1) / 2.0, 1.0);
  ScalarVolume v(Grid::fromAffine({n, n, n}, a), 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) v.at(i, j, k) = static_cast<float>(glm::length(v.grid.toWorld({i, j, k})));
  surfaces::IsosurfaceOptions o;
  o.insideIsLow = true;
  return surfaces::extractIsosurface(v, radius, o);
}
} // namespace

TEST(MeshChecks, ClosedIsosurfaceDoesNotSelfIntersect) {
  Mesh m = sphere(8, 24);
  EXPECT_EQ(surfaces::findSelfIntersections(m).intersectingPairs, 0u);
}

TEST(MeshChecks, CrossingTrianglesFoundAndRemoved) {
  Mesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, {3, 3, 0},
                 {10, 10, 10}, {11, 10, 10}, {10, 11, 10}};
  m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  auto r = surfaces::findSelfIntersections(m);
  EXPECT_EQ(r.intersectingPairs, 1u);
  EXPECT_EQ(r.faces, (std::vector<std::uint32_t>{0, 1}));
  std::size_t removed = 0;
  Mesh fixed = surfaces::removeSelfIntersections(m, &removed);
  EXPECT_EQ(removed, 2u);
  EXPECT_EQ(fixed.triangleCount(), 1u);
  EXPECT_EQ(fixed.positions.size(), 3u);
  EXPECT_EQ(surfaces::findSelfIntersections(fixed).intersectingPairs, 0u);
}

TEST(MeshChecks, RemeshingHitsTargetEdgeLength) {
  Mesh m = sphere(10, 30);
  Mesh r = surfaces::remeshIsotropic(m, 2.0);
  ASSERT_FALSE(r.empty());
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t t = 0; t < r.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      sum += glm::length(r.positions[r.indices[t + e]] - r.positions[r.indices[t + (e + 1) % 3]]);
      ++count;
    }
  EXPECT_NEAR(sum / count, 2.0, 0.4);
  for (const auto& p : r.positions) EXPECT_NEAR(glm::length(p), 10.0, 0.3);
}

// An edge that would make more than 5 million triangles is refused before CGAL allocates them; the message
// gives the shortest edge allowed, which remeshes.
TEST(MeshChecks, RemeshingRefusesAnEdgeTooShortForTheSurface) {
  const Mesh m = sphere(10, 30); // about 1257 mm^2: 5 million triangles at an edge of about 0.024 mm
  try {
    surfaces::remeshIsotropic(m, 0.001);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("at most 5 million"), std::string::npos) << what;
    const auto at = what.find("at least ");
    ASSERT_NE(at, std::string::npos) << what;
    const double shortest = std::stod(what.substr(at + 9));
    EXPECT_NEAR(shortest, std::sqrt(1257.0 / (std::sqrt(3.0) / 4 * 5e6)), 0.003);
  }
}

TEST(MeshChecks, DistanceToAPlane) {
  Mesh m;
  m.positions = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  surfaces::DistanceQuery q(m);
  glm::vec3 c;
  std::uint32_t tri = 99;
  EXPECT_NEAR(q.distance({1, 2, 3.5f}, &c, &tri), 3.5, 1e-6);
  EXPECT_NEAR(c.x, 1.0f, 1e-5);
  EXPECT_NEAR(c.z, 0.0f, 1e-6);
  EXPECT_LT(tri, 2u);
  EXPECT_NEAR(q.distance({13, 0, 4}), 5.0, 1e-6); // beyond the edge: distance to the border
}
