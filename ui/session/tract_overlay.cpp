// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_overlay.h"

#include "surfaces/analyses/near_surface.h"

#include <algorithm>

namespace dtf::session {

TractPick pickTracts(const Mesh& surface, double nearMm) {
  TractPick p;
  p.plane = surfaces::meshPlane(surface);
  p.nearOnly = !p.plane && nearMm > 0;
  return p;
}

TractSelection selectTracts(const Polylines& tracts, const Mesh& surface, double nearMm,
                            const std::atomic<bool>* cancel, std::size_t pointCap) {
  TractSelection s;
  s.pick = pickTracts(surface, nearMm);
  s.all = !s.pick.nearOnly;
  if (s.all) return s;
  surfaces::NearSurfaceOptions o;
  o.cancel = cancel;
  const surfaces::DistanceQuery query(surface);
  pointCap = std::max<std::size_t>(pointCap, 1);
  if (tracts.points.size() <= pointCap) {
    s.near = surfaces::selectNearSurface(tracts, query, nearMm, o);
    return s;
  }
  // Every m-th streamline, whole, so that about pointCap points are measured.
  s.lineStep = (tracts.points.size() + pointCap - 1) / pointCap;
  std::vector<std::uint32_t> sample;
  for (std::size_t i = 0; i < tracts.lineCount(); i += s.lineStep)
    sample.push_back(static_cast<std::uint32_t>(i));
  s.near = surfaces::selectNearSurface(tracts.subset(sample), query, nearMm, o);
  return s;
}

render::DisplayTracts tractOverlayDisplay(const Polylines& shown) {
  return render::prepareDisplayTracts(shown, render::kTractDisplayPointCap);
}

TractClip tractClip(const TractPick& pick, const TractOverlayOptions& o, const glm::vec3& forward,
                    const glm::vec3& centre) {
  TractClip c;
  if (pick.plane) {
    c.plane = *pick.plane;
    c.slabMm = static_cast<float>(o.clipMm > 0 ? o.clipMm : o.nearMm);
  } else {
    const glm::vec3 anchor = centre + static_cast<float>(o.clipDepthMm) * forward;
    c.plane = glm::vec4(forward, -glm::dot(forward, anchor));
    c.slabMm = static_cast<float>(o.clipMm);
  }
  return c;
}

} // namespace dtf::session
