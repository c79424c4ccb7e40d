// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/mesh_checks.h"

#include "io/model/error.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <iterator>
#include <vector>

namespace PMP = CGAL::Polygon_mesh_processing;

namespace dtf::surfaces {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using FaceIndex = SurfaceMesh::Face_index;

// Builds a Surface_mesh with face i = triangle i of `mesh` (the soup is used as is, so indices match).
SurfaceMesh toSurfaceMesh(const Mesh& mesh, bool orient) {
  std::vector<Point> points;
  points.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions)
    points.emplace_back(p.x, p.y, p.z);
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(mesh.triangleCount());
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
    polygons.push_back({mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]});
  if (orient) PMP::orient_polygon_soup(points, polygons); // may duplicate non-manifold vertices
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  return sm;
}

Mesh fromSurfaceMesh(const SurfaceMesh& sm) {
  Mesh m;
  std::vector<std::uint32_t> remap(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  for (auto v : sm.vertices()) {
    remap[v.idx()] = static_cast<std::uint32_t>(m.positions.size());
    const Point& p = sm.point(v);
    m.positions.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : sm.faces()) {
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      m.indices.push_back(remap[v.idx()]);
  }
  m.computeNormals();
  return m;
}
} // namespace

SelfIntersectionReport findSelfIntersections(const Mesh& mesh) {
  SelfIntersectionReport r;
  if (mesh.empty()) return r;
  // A triangle soup keeps face indices equal to the input's; self_intersections works on any face graph,
  // and combinatorially adjacent faces (shared edge or vertex) only count when they truly overlap.
  SurfaceMesh sm = toSurfaceMesh(mesh, false);
  if (sm.number_of_faces() != mesh.triangleCount()) {
    // Non-manifold input: orient (duplicates vertices where needed), faces stay in input order.
    sm = toSurfaceMesh(mesh, true);
  }
  if (sm.number_of_faces() != mesh.triangleCount())
    throw InputError("mesh is not a valid polygon mesh (" +
                     std::to_string(mesh.triangleCount() - sm.number_of_faces()) +
                     " triangles could not be added)");
  std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
  PMP::self_intersections(sm, std::back_inserter(pairs));
  r.intersectingPairs = pairs.size();
  for (const auto& [a, b] : pairs) {
    r.faces.push_back(static_cast<std::uint32_t>(a.idx()));
    r.faces.push_back(static_cast<std::uint32_t>(b.idx()));
  }
  std::sort(r.faces.begin(), r.faces.end());
  r.faces.erase(std::unique(r.faces.begin(), r.faces.end()), r.faces.end());
  return r;
}

Mesh removeSelfIntersections(const Mesh& mesh, std::size_t* removed) {
  SelfIntersectionReport r = findSelfIntersections(mesh);
  if (removed) *removed = r.faces.size();
  if (r.faces.empty()) return mesh;
  Mesh out;
  out.positions = mesh.positions;
  std::size_t next = 0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (next < r.faces.size() && r.faces[next] == t) {
      ++next;
      continue;
    }
    out.indices.insert(out.indices.end(), mesh.indices.begin() + 3 * t, mesh.indices.begin() + 3 * t + 3);
  }
  // Drop unused vertices.
  std::vector<std::int64_t> remap(out.positions.size(), -1);
  std::vector<glm::vec3> pos;
  for (auto& i : out.indices) {
    if (remap[i] < 0) {
      remap[i] = static_cast<std::int64_t>(pos.size());
      pos.push_back(out.positions[i]);
    }
    i = static_cast<std::uint32_t>(remap[i]);
  }
  out.positions = std::move(pos);
  out.computeNormals();
  return out;
}

Mesh remeshIsotropic(const Mesh& mesh, double targetEdgeMm, int iterations) {
  if (!(targetEdgeMm > 0)) throw UsageError("remeshing edge length must be positive");
  // The result has about area / (sqrt(3)/4 e^2) triangles; CGAL needs some 200 bytes each while remeshing.
  constexpr double kMaxTriangles = 5e6;
  double area = 0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::dvec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                     c = mesh.positions[mesh.indices[t + 2]];
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const double equilateral = std::sqrt(3.0) / 4.0;
  if (area / (equilateral * targetEdgeMm * targetEdgeMm) > kMaxTriangles) {
    char why[200];
    std::snprintf(
        why, sizeof why,
        "remeshing to %g mm edges would make about %.3g triangles of this %.0f mm^2 surface (at most "
        "5 million): give an edge of at least %.2g mm",
        targetEdgeMm, area / (equilateral * targetEdgeMm * targetEdgeMm), area,
        std::sqrt(area / (equilateral * kMaxTriangles)) * 1.01);
    throw UsageError(why);
  }
  SurfaceMesh sm = toSurfaceMesh(mesh, true);
  PMP::isotropic_remeshing(faces(sm), targetEdgeMm, sm,
                           PMP::parameters::number_of_iterations(iterations).protect_constraints(false));
  sm.collect_garbage();
  return fromSurfaceMesh(sm);
}

struct DistanceQuery::Impl {
  using Triangle = Kernel::Triangle_3;
  using Iterator = std::vector<Triangle>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  std::vector<Triangle> triangles;
  Tree tree;
};

DistanceQuery::DistanceQuery(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  if (mesh.empty()) throw InputError("distance query on an empty mesh");
  impl_->triangles.reserve(mesh.triangleCount());
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    auto p = [&](int k) {
      const glm::vec3& v = mesh.positions[mesh.indices[t + k]];
      return Point(v.x, v.y, v.z);
    };
    impl_->triangles.emplace_back(p(0), p(1), p(2));
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

DistanceQuery::~DistanceQuery() = default;

double DistanceQuery::distance(const glm::vec3& p, glm::vec3* closest, std::uint32_t* triangle) const {
  Point q(p.x, p.y, p.z);
  auto hit = impl_->tree.closest_point_and_primitive(q);
  if (closest) *closest = glm::vec3(hit.first.x(), hit.first.y(), hit.first.z());
  if (triangle) *triangle = static_cast<std::uint32_t>(hit.second - impl_->triangles.cbegin());
  return std::sqrt(CGAL::to_double(CGAL::squared_distance(q, hit.first)));
}

namespace {
// AABB traversal for "is a triangle within sqrt(r2) of q": enters only boxes within that distance and stops
// at the first triangle found.
template <typename Primitive> struct WithinTraits {
  Point q;
  double r2;
  bool found = false;
  typename Primitive::Id hit{};
  bool go_further() const { return !found; }
  void intersection(const Point&, const Primitive& p) {
    if (CGAL::squared_distance(q, *p.id()) <= r2) found = true, hit = p.id();
  }
  template <typename Node> bool do_intersect(const Point&, const Node& node) const {
    const CGAL::Bbox_3& b = node.bbox();
    double d2 = 0;
    const double c[3] = {q.x(), q.y(), q.z()};
    for (int i = 0; i < 3; ++i) {
      const double lo = b.min(i), hi = b.max(i);
      const double d = c[i] < lo ? lo - c[i] : c[i] > hi ? c[i] - hi : 0.0;
      d2 += d * d;
    }
    return d2 <= r2;
  }
};
} // namespace

bool DistanceQuery::within(const glm::vec3& p, double r) const {
  WithinTraits<Impl::Primitive> t{Point(p.x, p.y, p.z), r * r};
  impl_->tree.traversal(t.q, t);
  return t.found;
}

bool DistanceQuery::within(const glm::vec3& p, double r, std::uint32_t* hint) const {
  const Point q(p.x, p.y, p.z);
  if (*hint < impl_->triangles.size() && CGAL::squared_distance(q, impl_->triangles[*hint]) <= r * r) return true;
  WithinTraits<Impl::Primitive> t{q, r * r};
  impl_->tree.traversal(t.q, t);
  if (t.found) *hint = static_cast<std::uint32_t>(t.hit - impl_->triangles.cbegin());
  return t.found;
}

void DistanceQuery::bounds(glm::vec3& lo, glm::vec3& hi) const {
  const auto box = impl_->tree.bbox();
  lo = glm::vec3(box.xmin(), box.ymin(), box.zmin());
  hi = glm::vec3(box.xmax(), box.ymax(), box.zmax());
}

} // namespace dtf::surfaces
