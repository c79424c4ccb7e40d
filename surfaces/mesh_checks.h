// SPDX-License-Identifier: GPL-3.0-or-later
// Geometric checks and queries on meshes, backed by CGAL (this module's only CGAL translation unit):
// self-intersection detection and repair (the fabric needs non-self-intersecting surfaces), isotropic
// remeshing, and an AABB-tree distance query used to pick tract points near a surface.
#pragma once

#include "io/model/geometry.h"

#include <memory>
#include <vector>

namespace dtf::surfaces {

struct SelfIntersectionReport {
  std::size_t intersectingPairs = 0;
  std::vector<std::uint32_t> faces; // triangles involved in at least one intersection (sorted, unique)
};

// Pairs of triangles that intersect other than along a shared edge or vertex.
SelfIntersectionReport findSelfIntersections(const Mesh& mesh);
// Removes the triangles involved in self-intersections (leaves small holes there; the fabric tolerates
// holes, not overlaps) and unused vertices. Returns the repaired mesh; `removed` gets the triangle count.
Mesh removeSelfIntersections(const Mesh& mesh, std::size_t* removed = nullptr);
// Isotropic remeshing to the target edge length (mm), keeping borders; normals recomputed. Throws UsageError
// when the edge would make more than 5 million triangles of this surface (the message gives the shortest
// edge).
Mesh remeshIsotropic(const Mesh& mesh, double targetEdgeMm, int iterations = 3);

// Closest-point queries against a fixed mesh (CGAL AABB tree and its search tree built once; const queries
// may run on several threads at once).
class DistanceQuery {
public:
  explicit DistanceQuery(const Mesh& mesh);
  ~DistanceQuery();
  DistanceQuery(const DistanceQuery&) = delete;
  DistanceQuery& operator=(const DistanceQuery&) = delete;

  // Euclidean distance (mm) from `p` to the surface; the closest point and its triangle when asked.
  double distance(const glm::vec3& p, glm::vec3* closest = nullptr, std::uint32_t* triangle = nullptr) const;
  // True when the surface comes within r mm of `p` (distance <= r): a traversal that stops at the first
  // triangle found and never enters boxes farther than r, cheaper than distance().
  bool within(const glm::vec3& p, double r) const;
  // within() that first tries triangle `*hint` (e.g. the one found for the previous point of a line: a
  // triangle within r decides at once) and leaves the triangle found, if any, in *hint. Same answer.
  bool within(const glm::vec3& p, double r, std::uint32_t* hint) const;
  // Bounding box of the mesh (world mm).
  void bounds(glm::vec3& lo, glm::vec3& hi) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace dtf::surfaces
