// SPDX-License-Identifier: GPL-3.0-or-later
// The letters a pane shows at its edges: the anatomical side the camera puts there.
#pragma once

#include <glm/glm.hpp>

namespace dtf::session {

// The anatomical letter of a world direction's dominant axis (RAS: +x R, +y A, +z S; negative: L, P, I),
// e.g. of the camera's right vector for the pane's right edge.
inline const char* anatomicalLabel(const glm::dvec3& d) {
  const glm::dvec3 a = glm::abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0 ? "R" : "L";
  if (a.y >= a.z) return d.y >= 0 ? "A" : "P";
  return d.z >= 0 ? "S" : "I";
}

} // namespace dtf::session
