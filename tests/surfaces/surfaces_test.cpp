// SPDX-License-Identifier: GPL-3.0-or-later
// Isosurfaces, slices and mesh files against closed forms.
#include "io/model/error.h"
#include "support/test_env.h"
#include "surfaces/isosurface.h"
#include "surfaces/mesh_io.h"
#include "surfaces/slices.h"

#include <cmath>

using namespace dtf;

namespace {
// Distance-to-centre field on a grid with the given affine (centre at world origin).
ScalarVolume sphereDistance(const glm::dmat4& affine, int n) {
  ScalarVolume v(Grid::fromAffine({n, n, n}, affine), 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) v.at(i, j, k) = static_cast<float>(glm::length(v.grid.toWorld({i, j, k})));
  return v;
}
glm::dmat4 affine(double sx, double sy, double sz, int n) {
  glm::dmat4 a(1.0);
  a[0][0] = sx;
  a[1][1] = sy;
  a[2][2] = sz;
  a[3] = glm::dvec4(-sx * (n - 1) / 2.0, -sy * (n - 1) / 2.0, -sz * (n - 1) / 2.0, 1.0);
  return a;
}
double signedVolume(const Mesh& m) {
  double v = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    v += glm::dot(glm::dvec3(m.positions[m.indices[t]]),
                  glm::cross(glm::dvec3(m.positions[m.indices[t + 1]]), glm::dvec3(m.positions[m.indices[t + 2]]))) /
         6.0;
  return v;
}
} // namespace

class SphereIso : public ::testing::TestWithParam<double> {};

TEST_P(SphereIso, RadiusNormalsAndWindingInWorldSpace) {
  const int n = 40;
  const double sx = GetParam(); // -1 for a LAS affine
  ScalarVolume v = sphereDistance(affine(sx, 1, 1, n), n);
  surfaces::IsosurfaceOptions o;
  o.insideIsLow = true; // distance grows outward
  Mesh m = surfaces::extractIsosurface(v, 12.0, o);
  ASSERT_GT(m.triangleCount(), 1000u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  double maxErr = 0, minDot = 1;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    glm::dvec3 p(m.positions[i]);
    maxErr = std::max(maxErr, std::abs(glm::length(p) - 12.0));
    minDot = std::min(minDot, glm::dot(glm::normalize(p), glm::dvec3(m.normals[i])));
  }
  EXPECT_LT(maxErr, 0.05);
  EXPECT_GT(minDot, 0.95); // outward normals
  // Counter-clockwise seen from outside: positive enclosed volume close to 4/3 pi r^3.
  EXPECT_NEAR(signedVolume(m), 4.0 / 3.0 * M_PI * 1728.0, 0.02 * 4.0 / 3.0 * M_PI * 1728.0);
}
INSTANTIATE_TEST_SUITE_P(Affines, SphereIso, ::testing::Values(1.0, -1.0));

TEST(Isosurface, ClosedAtTheBorderAndMasked) {
  // A slab of high values touching two faces of the grid: closing at the border caps it.
  const int n = 12;
  ScalarVolume v(Grid::fromAffine({n, n, n}, glm::dmat4(1.0)), 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) v.at(i, j, k) = (j >= 3 && j <= 8 && k >= 3 && k <= 8) ? 1.0f : 0.0f;
  surfaces::IsosurfaceOptions open;
  open.closeAtBorder = false;
  Mesh closed = surfaces::extractIsosurface(v, 0.5);
  Mesh opened = surfaces::extractIsosurface(v, 0.5, open);
  EXPECT_GT(closed.triangleCount(), opened.triangleCount());
  EXPECT_GT(signedVolume(closed), 0.9 * 12 * 6 * 6); // a closed box of about 12 x 6 x 6 (plus the caps)
  MaskVolume mask(v.grid, 1, 0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < 6; ++i) mask.at(i, j, k) = 1;
  surfaces::IsosurfaceOptions masked;
  masked.mask = &mask;
  Mesh half = surfaces::extractIsosurface(v, 0.5, masked);
  for (const auto& p : half.positions) EXPECT_LT(p.x, 6.0f);
}

TEST(Isosurface, NoCrossingGivesEmptyMesh) {
  ScalarVolume v = sphereDistance(affine(1, 1, 1, 10), 10);
  EXPECT_TRUE(surfaces::extractIsosurface(v, 100.0).empty());
}

TEST(Isosurface, SmallComponentsDropped) {
  const int n = 40;
  ScalarVolume v(Grid::fromAffine({n, n, n}, glm::dmat4(1.0)), 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double big = 10 - glm::length(glm::dvec3(i - 15, j - 20, k - 20));
        double small = 2 - glm::length(glm::dvec3(i - 33, j - 20, k - 20));
        v.at(i, j, k) = static_cast<float>(std::max(big, small));
      }
  Mesh all = surfaces::extractIsosurface(v, 0.0);
  surfaces::IsosurfaceOptions o;
  o.minComponentFraction = 0.2;
  Mesh kept = surfaces::extractIsosurface(v, 0.0, o);
  EXPECT_LT(kept.triangleCount(), all.triangleCount());
  for (const auto& p : kept.positions) EXPECT_LT(p.x, 27.0f);
}

TEST(Slices, AxisMappingAndGeometryOnLasGrid) {
  glm::dmat4 las(1.0);
  las[0][0] = -3;
  las[1][1] = 3;
  las[2][2] = 3;
  las[3] = glm::dvec4(108, -98, -23, 1);
  Grid g = Grid::fromAffine({72, 72, 39}, las);
  EXPECT_EQ(surfaces::voxelAxisFor(g, surfaces::SliceAxis::Axial), 2);
  EXPECT_EQ(surfaces::voxelAxisFor(g, surfaces::SliceAxis::Sagittal), 0);
  EXPECT_EQ(surfaces::sliceCount(g, surfaces::SliceAxis::Coronal), 72);
  Mesh m = surfaces::makeSlice(g, surfaces::SliceAxis::Axial, 22);
  EXPECT_EQ(m.triangleCount(), 71u * 71u * 2u);
  for (const auto& p : m.positions) EXPECT_FLOAT_EQ(p.z, -23 + 66);
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f) << "triangle " << t / 3 << " faces away from superior";
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_THROW(surfaces::makeSlice(g, surfaces::SliceAxis::Axial, 39), InputError);
}

TEST(Slices, ClippedToMask) {
  Grid g = Grid::fromAffine({10, 10, 10}, glm::dmat4(1.0));
  ScalarVolume mask(g, 1);
  for (int j = 2; j <= 4; ++j)
    for (int i = 2; i <= 5; ++i) mask.at(i, j, 3) = 1;
  surfaces::SliceOptions o;
  o.clip = &mask;
  Mesh m = surfaces::makeSlice(g, surfaces::SliceAxis::Axial, 3, o);
  EXPECT_EQ(m.triangleCount(), 3u * 2u * 2u); // 3x2 cells inside a 4x3 block of voxels
  EXPECT_EQ(m.positions.size(), 12u);
}

TEST(Slices, ObliquePlaneStaysInsideGrid) {
  Grid g = Grid::fromAffine({20, 20, 20}, glm::dmat4(1.0));
  Mesh m = surfaces::makePlane(g, {10, 10, 10}, {1, 1, 1}, 1.0);
  ASSERT_GT(m.triangleCount(), 100u);
  for (const auto& p : m.positions) {
    EXPECT_NEAR(glm::dot(glm::dvec3(p) - glm::dvec3(10), glm::normalize(glm::dvec3(1, 1, 1))), 0.0, 1e-4);
    EXPECT_GE(p.x, -1e-4);
    EXPECT_LE(p.x, 19.0001);
  }
  EXPECT_TRUE(surfaces::makePlane(g, {100, 100, 100}, {0, 0, 1}, 1.0).empty());
}

TEST(MeshIo, RoundTripPlyVtpObj) {
  ScalarVolume v = sphereDistance(affine(1, 1, 1, 20), 20);
  Mesh m = surfaces::extractIsosurface(v, 6.0);
  auto dir = dtf::test::scratchDir();
  for (const char* ext : {".ply", ".vtp", ".obj"}) {
    std::string path = (dir / (std::string("sphere") + ext)).string();
    surfaces::writeMesh(path, m);
    Mesh back = surfaces::readMesh(path);
    EXPECT_EQ(back.triangleCount(), m.triangleCount()) << ext;
    ASSERT_EQ(back.positions.size(), m.positions.size()) << ext;
    for (std::size_t i = 0; i < m.positions.size(); i += 37)
      EXPECT_LT(glm::length(back.positions[i] - m.positions[i]), 1e-4f) << ext;
  }
  EXPECT_THROW(surfaces::readMesh((dir / "missing.ply").string()), InputError);
  EXPECT_THROW(surfaces::writeMesh((dir / "x.stl").string(), m), InputError);
}

TEST(MeshIo, RealTractFileIsNotAMesh) {
  DTF_SHARED_FILE(path, "iu_prisma_dwi/derived/tracks_det_first500.vtk");
  EXPECT_THROW(surfaces::readMesh(path.string()), InputError); // polylines, no triangles
}
