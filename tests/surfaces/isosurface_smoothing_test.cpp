// SPDX-License-Identifier: GPL-3.0-or-later
// Windowed-sinc smoothing of isosurfaces: the lumps of a coarse, hard-edged volume go, the surface stays
// where it was (no vertex moves further than the bound, clamped and reported), normals point out.
#include "surfaces/isosurface.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dtf;

namespace {

// A ball of radius 7.3 voxels as a binary volume (1 inside): its 0.5 isosurface is a staircase of voxels.
ScalarVolume binaryBall(glm::dvec3& centreWorld) {
  glm::dmat4 a(1.0);
  for (int c = 0; c < 3; ++c)
    a[c][c] = 2.0; // 2 mm voxels
  a[3] = glm::dvec4(10, -20, 5, 1);
  ScalarVolume v(Grid::fromAffine(glm::ivec3(24), a), 1);
  const glm::dvec3 c(11.5, 11.5, 11.5);
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i)
        v.data[v.grid.index(i, j, k)] = glm::length(glm::dvec3(i, j, k) - c) < 7.3 ? 1.0f : 0.0f;
  centreWorld = v.grid.toWorld(c);
  return v;
}

// Spread of the vertices' distance from the centre (mm), and the fraction of normals pointing outward.
void measure(const Mesh& m, const glm::dvec3& c, double& radiusSd, double& outward) {
  double s = 0, s2 = 0;
  int out = 0;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(m.positions[i]) - c;
    const double r = glm::length(d);
    s += r;
    s2 += r * r;
    if (glm::dot(glm::dvec3(m.normals[i]), d) > 0) ++out;
  }
  const double n = static_cast<double>(m.positions.size());
  radiusSd = std::sqrt(std::max(s2 / n - (s / n) * (s / n), 0.0));
  outward = out / n;
}

} // namespace

TEST(IsosurfaceSmoothing, SmoothsALumpySurfaceWithinTheShiftBound) {
  glm::dvec3 centre;
  const ScalarVolume ball = binaryBall(centre);
  surfaces::IsosurfaceOptions raw;
  const Mesh lumpy = surfaces::extractIsosurface(ball, 0.5, raw);
  surfaces::IsosurfaceOptions smooth = raw;
  smooth.meshSmoothIterations = 15;
  smooth.maxShiftVoxels = 0.5;
  surfaces::SmoothingReport report;
  const Mesh smoothed = surfaces::extractIsosurface(ball, 0.5, smooth, &report);
  ASSERT_EQ(lumpy.positions.size(), smoothed.positions.size()); // same vertices, moved
  ASSERT_EQ(report.vertices, smoothed.positions.size());

  // The bound, measured independently in mm: 0.5 voxel = 1 mm on this grid.
  double maxShift = 0;
  for (std::size_t i = 0; i < lumpy.positions.size(); ++i)
    maxShift = std::max(maxShift, glm::length(glm::dvec3(smoothed.positions[i] - lumpy.positions[i])));
  EXPECT_LE(maxShift, 1.0 + 1e-4);
  EXPECT_GT(maxShift, 0.1); // it did move
  EXPECT_LE(report.meanShiftVoxels, 0.5);
  EXPECT_NEAR(std::min(report.maxShiftVoxels, 0.5), maxShift / 2.0, 1e-3);

  double sdLumpy, sdSmooth, outLumpy, outSmooth;
  measure(lumpy, centre, sdLumpy, outLumpy);
  measure(smoothed, centre, sdSmooth, outSmooth);
  // Rounder: the spread of the radius falls (the staircase's lumps go).
  EXPECT_LT(sdSmooth, 0.6 * sdLumpy) << sdLumpy << " -> " << sdSmooth;
  // Normals recomputed from the smoothed mesh, still pointing out of the object.
  EXPECT_GT(outSmooth, 0.99);

  // A tight bound clamps most vertices and is reported.
  smooth.maxShiftVoxels = 0.05;
  surfaces::SmoothingReport tight;
  const Mesh clamped = surfaces::extractIsosurface(ball, 0.5, smooth, &tight);
  EXPECT_GT(tight.clamped, tight.vertices / 4);
  EXPECT_GT(tight.maxShiftVoxels, 0.05);
  for (std::size_t i = 0; i < lumpy.positions.size(); ++i)
    ASSERT_LE(glm::length(glm::dvec3(clamped.positions[i] - lumpy.positions[i])), 0.1 + 1e-4);
}
