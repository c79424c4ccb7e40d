// SPDX-License-Identifier: GPL-3.0-or-later
// Which tracts lie on a surface: the segments near it (through the distance query of surfaces/mesh_checks.h)
// and the plane of a planar surface (slices and oblique planes), around which tracts are drawn in a slab.
#pragma once

#include "io/model/geometry.h"
#include "surfaces/mesh_checks.h"

#include <atomic>
#include <glm/glm.hpp>
#include <optional>

namespace dtf::surfaces {

struct NearSurfaceOptions {
  int threads = 0; // 0 = all hardware threads
  bool exhaustive =
      false; // one exact distance query per point: the reference the fast path is tested against
  const std::atomic<bool>* cancel = nullptr; // set: stop early and return an empty selection
};

// Keeps the tract segments whose two end points both lie within maxMm (world mm) of the surface; each run
// of consecutive kept segments becomes its own line. maxMm <= 0 keeps every line as it is. A line whose
// bounding box misses the surface's box grown by maxMm is skipped whole, as is each point outside that box;
// the rest ask DistanceQuery::within (a traversal that stops at the first triangle within maxMm, 3-5x faster
// than a closest-point query per point). Lines are split over threads; the output is in input order
// whatever the thread count. Per-point data follow the kept points (per-streamline data and groups do not).
Polylines selectNearSurface(const Polylines& lines, const DistanceQuery& surface, double maxMm,
                            const NearSurfaceOptions& options = {});

// The plane (unit normal n, offset w: dot(n, p) + w = 0, world mm) of a mesh whose vertices all lie within
// toleranceMm of it, else nullopt (curved or empty meshes).
std::optional<glm::vec4> meshPlane(const Mesh& mesh, double toleranceMm = 1e-3);

} // namespace dtf::surfaces
