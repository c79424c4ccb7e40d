// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_overlay.h"

#include "surfaces/analyses/near_surface.h"

namespace dtf::session {

TractPick pickTracts(const Mesh& surface, double nearMm) {
  TractPick p;
  p.plane = surfaces::meshPlane(surface);
  p.nearOnly = !p.plane && nearMm > 0;
  return p;
}

TractSelection selectTracts(const Polylines& tracts, const Mesh& surface, double nearMm,
                            const std::atomic<bool>* cancel) {
  TractSelection s;
  s.pick = pickTracts(surface, nearMm);
  s.all = !s.pick.nearOnly;
  if (s.all) return s;
  surfaces::NearSurfaceOptions o;
  o.cancel = cancel;
  s.near = surfaces::selectNearSurface(tracts, surfaces::DistanceQuery(surface), nearMm, o);
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
