// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh::isClosedOutward: the closed-surface test behind back-face culling in the renderer.
#include "io/model/geometry.h"

#include <gtest/gtest.h>

using namespace dtf;

namespace {

// A regular octahedron around the origin, counter-clockwise seen from outside.
Mesh octahedron() {
  Mesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return m;
}

// The same octahedron with three vertices per face (as OBJ/STL exporters write it), positions jittered
// far below the weld tolerance.
Mesh perFaceOctahedron(float jitter) {
  Mesh shared = octahedron(), m;
  for (std::size_t i = 0; i < shared.indices.size(); ++i) {
    glm::vec3 p = shared.positions[shared.indices[i]];
    p.x += (i % 2 ? jitter : -jitter);
    m.positions.push_back(p);
    m.indices.push_back(static_cast<std::uint32_t>(i));
  }
  return m;
}

} // namespace

TEST(MeshClosure, ClosedOutwardSurfaceIsRecognised) {
  EXPECT_TRUE(octahedron().isClosedOutward());
  EXPECT_TRUE(perFaceOctahedron(0.0f).isClosedOutward());
  EXPECT_TRUE(perFaceOctahedron(1e-7f).isClosedOutward()); // welded within 2^-20 of the extent
}

TEST(MeshClosure, InwardWindingIsNotOutward) {
  Mesh m = octahedron();
  for (std::size_t t = 0; t < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
  EXPECT_FALSE(m.isClosedOutward());
}

TEST(MeshClosure, OpenOrInconsistentSurfacesAreNot) {
  Mesh hole = octahedron();
  hole.indices.resize(hole.indices.size() - 3); // one face missing
  EXPECT_FALSE(hole.isClosedOutward());

  Mesh flipped = octahedron(); // one face wound the wrong way
  std::swap(flipped.indices[1], flipped.indices[2]);
  EXPECT_FALSE(flipped.isClosedOutward());

  Mesh gap = perFaceOctahedron(0.01f); // cracks of 1% of the extent are not welded
  EXPECT_FALSE(gap.isClosedOutward());

  Mesh plane;
  plane.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  plane.indices = {0, 1, 2, 0, 2, 3};
  EXPECT_FALSE(plane.isClosedOutward());

  Mesh doubled = octahedron(); // every face twice: each edge shared by four triangles
  const auto n = doubled.indices.size();
  for (std::size_t i = 0; i < n; ++i) doubled.indices.push_back(doubled.indices[i]);
  EXPECT_FALSE(doubled.isClosedOutward());

  EXPECT_FALSE(Mesh{}.isClosedOutward());
  Mesh bad = octahedron();
  bad.indices[0] = 99; // out of range
  EXPECT_FALSE(bad.isClosedOutward());
}

TEST(MeshClosure, TwoSeparateClosedSurfacesAreClosed) {
  Mesh a = octahedron(), b = octahedron();
  const auto offset = static_cast<std::uint32_t>(a.positions.size());
  for (auto p : b.positions) a.positions.push_back(p + glm::vec3(5, 0, 0));
  for (auto i : b.indices) a.indices.push_back(i + offset);
  EXPECT_TRUE(a.isClosedOutward());
}
