// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh::isClosedOutward: the closed-surface test behind back-face culling in the renderer; PointArray, the
// positions of tracts, viewed in place or owned.
#include "io/model/geometry.h"

#include <gtest/gtest.h>
#include <iterator>
#include <memory>

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

// A viewed PointArray reads in place and copies itself on the first change, leaving the viewed memory as it
// was; copies share the view until they change.
TEST(PointArray, AViewIsReadInPlaceAndCopiedOnTheFirstChange) {
  auto memory = std::make_shared<std::vector<glm::vec3>>(
      std::vector<glm::vec3>{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}});
  const glm::vec3* at = memory->data();
  dtf::PointArray a = dtf::PointArray::view(memory, at, 3); // the first three only
  ASSERT_TRUE(a.viewed());
  EXPECT_EQ(a.size(), 3u);
  const dtf::PointArray& ca = a;
  EXPECT_EQ(ca.data(), at) << "const access reads the viewed memory";
  EXPECT_EQ(ca[2], glm::vec3(7, 8, 9));
  EXPECT_EQ(ca.back(), glm::vec3(7, 8, 9));
  EXPECT_EQ(std::distance(ca.begin(), ca.end()), 3);
  dtf::PointArray b = a; // shares the view
  EXPECT_TRUE(b.viewed());
  EXPECT_EQ(static_cast<const dtf::PointArray&>(b).data(), at);
  EXPECT_TRUE(a == b);
  // A change copies the view first; the viewed memory and the other copy keep their values.
  b[1] = glm::vec3(0);
  EXPECT_FALSE(b.viewed());
  EXPECT_NE(static_cast<const dtf::PointArray&>(b).data(), at);
  EXPECT_EQ((*memory)[1], glm::vec3(4, 5, 6));
  EXPECT_EQ(ca[1], glm::vec3(4, 5, 6));
  EXPECT_FALSE(a == b);
  // Inserting at a place in a view inserts at that place of the copy.
  dtf::PointArray c = a;
  c.insert(static_cast<const dtf::PointArray&>(c).begin() + 1, glm::vec3(-1));
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], glm::vec3(1, 2, 3));
  EXPECT_EQ(c[1], glm::vec3(-1));
  EXPECT_EQ(c[3], glm::vec3(7, 8, 9));
  // The view keeps its owner alive.
  const std::weak_ptr<std::vector<glm::vec3>> watch = memory;
  memory.reset();
  EXPECT_FALSE(watch.expired());
  EXPECT_EQ(ca[0], glm::vec3(1, 2, 3));
  a.clear();
  b = dtf::PointArray{};
  EXPECT_TRUE(watch.expired()) << "the last view gone, the owner goes";
  // A vector converts; take() moves it out.
  dtf::PointArray d = std::vector<glm::vec3>{{1, 1, 1}};
  EXPECT_FALSE(d.viewed());
  EXPECT_EQ(d.take(), std::vector<glm::vec3>{glm::vec3(1)});
  EXPECT_TRUE(d.empty());
}
