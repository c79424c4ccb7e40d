// SPDX-License-Identifier: GPL-3.0-or-later
// Which tracts a surface shows and where they are clipped: one rule for `dtfabric render --tracts` and the
// viewer.
//   planar surface (slice, plane): every tract, clipped to a slab around the surface's plane of half-width
//     clipMm when given, else nearMm (0 and 0: no clip);
//   curved surface: the segments within nearMm of it (0: every tract), clipped to a slab of half-width
//     clipMm (0: none) around the plane that faces the camera through the surface's centre, moved clipDepthMm
//     away from the viewer.
// What is drawn of the selection is its display decimation (render::prepareDisplayTracts: at most
// render::kTractDisplayPointCap points, every n-th point of each line) with its levels of detail.
#pragma once

#include "io/model/geometry.h"
#include "render/tract_renderer.h"

#include <atomic>
#include <glm/glm.hpp>
#include <optional>

namespace dtf::session {

struct TractOverlayOptions {
  double nearMm = 3.0;
  double clipMm = 0.0;
  double clipDepthMm = 0.0;
};

// What to select for a surface: the plane of a planar surface (every tract is drawn), else whether only the
// segments near the surface are (nearMm > 0).
struct TractPick {
  std::optional<glm::vec4> plane; // unit normal, offset: dot(n, p) + w = 0 (world mm)
  bool nearOnly = false;
};
TractPick pickTracts(const Mesh& surface, double nearMm);

// Points a curved surface's near-surface selection measures at most: past it, an even sample of the
// streamlines (every m-th, whole) is measured. The selection only feeds the display, which keeps at most
// render::kTractDisplayPointCap points; measuring every point of a whole-brain tractogram (500 M points
// for 10 M streamlines) against the surface takes many minutes.
inline constexpr std::size_t kNearSurfacePointCap = render::kTractDisplayPointCap;
// The quick first pass after a region change near a curved surface: about a 1/7 of kNearSurfacePointCap
// is measured, so the bundle redraws at once; the full pass follows when no newer change comes.
inline constexpr std::size_t kNearSurfaceQuickPointCap = 150'000;

// The tracts `surface` shows: `all` (every tract: a planar surface, or nearMm 0) or the pieces within nearMm
// of it in `near` (surfaces/analyses/near_surface.h), of every lineStep-th streamline (1 up to
// pointCap points). A set `cancel` stops early with an empty `near`.
struct TractSelection {
  TractPick pick;
  bool all = true;
  Polylines near;
  std::size_t lineStep = 1;
};
TractSelection selectTracts(const Polylines& tracts, const Mesh& surface, double nearMm,
                            const std::atomic<bool>* cancel = nullptr,
                            std::size_t pointCap = kNearSurfacePointCap);

// What the overlay uploads for `shown` (the selection): its display decimation and levels of detail.
render::DisplayTracts tractOverlayDisplay(const Polylines& shown);

// The clip slab for one camera: plane (unit normal, offset) and half-width in mm (0: no clip).
struct TractClip {
  glm::vec4 plane{0, 0, 1, 0};
  float slabMm = 0.0f;
};
// `pick` from pickTracts, `forward` the camera's view direction, `centre` the centre of the surface's bounds.
TractClip tractClip(const TractPick& pick, const TractOverlayOptions& options, const glm::vec3& forward,
                    const glm::vec3& centre);

} // namespace dtf::session
