// SPDX-License-Identifier: GPL-3.0-or-later
// Geometry passed between surfaces, tracts and render: triangle meshes and polylines in world RAS mm.
#pragma once

#include "io/model/point_array.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace dtf {

struct Mesh {
  std::vector<glm::vec3> positions; // world RAS mm
  std::vector<glm::vec3> normals;   // unit, per vertex (may be empty until computed)
  std::vector<std::uint32_t> indices; // 3 per triangle, counter-clockwise seen from outside

  std::size_t triangleCount() const { return indices.size() / 3; }
  bool empty() const { return indices.empty(); }
  // Area-weighted vertex normals from the triangles.
  void computeNormals();
  void bounds(glm::vec3& lo, glm::vec3& hi) const;
  // True when the triangles enclose a volume with outward winding: every edge (vertices at the same
  // position count as one) is shared by exactly two triangles that traverse it in opposite directions,
  // and the signed volume is positive. Then, seen from outside, every back face is hidden behind a front
  // face, so a renderer may cull back faces. O(n log n) in the vertices, O(n) in the triangles.
  bool isClosedOutward() const;
};

// Named values attached to tracts: `components` floats per streamline (per-line data) or per point
// (per-point data), item-major: values[item * components + c].
struct TractValues {
  std::string name;
  int components = 1;
  std::vector<float> values;
};

// A named subset of streamlines (a bundle), as indices into the lines.
struct TractGroup {
  std::string name;
  std::vector<std::uint32_t> lines;
};

struct Polylines {
  PointArray points;                   // world RAS mm, all lines concatenated (possibly viewed in a file)
  std::vector<std::uint32_t> offsets;  // start of each line in `points`, plus a final entry = points.size()
  std::vector<TractValues> perLine;    // each with lineCount() * components values
  std::vector<TractValues> perPoint;   // each with points.size() * components values
  std::vector<TractGroup> groups;

  std::size_t lineCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  // Empty when the data, groups and offsets agree with the points; otherwise what is wrong.
  std::string inconsistency() const;
  // The streamlines listed in `lines` (in that order) with their per-streamline and per-point data; groups
  // are not carried (their indices refer to the full set).
  Polylines subset(const std::vector<std::uint32_t>& lines) const;
  // Appends the points [begin, end) of `src` with their per-point data (the arrays of `src` are created here
  // when this set has none yet); does not close a line (push the offset after the last point).
  void appendPoints(const Polylines& src, std::size_t begin, std::size_t end);
  // One value per point of the data named `name` (per-point, or per-streamline repeated along each line;
  // several components give their Euclidean norm). Empty when there is no such data.
  std::vector<float> valuesPerPoint(const std::string& name) const;
};

} // namespace dtf
