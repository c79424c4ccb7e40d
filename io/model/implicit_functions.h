// SPDX-License-Identifier: GPL-3.0-or-later
// Implicit functions whose Hessians are the analytic tensor fields of the phantoms and reference scenes
// (paper §3.1), in closed form.
#pragma once

#include <glm/glm.hpp>

namespace dtf {

// Bretzel5 (paper Eq. 14): f = ((x^2 + y^2/4 - 1)(x^2/4 + y^2 - 1))^2 + z^2 - 0.1, with its gradient and
// Hessian, at a point in function units.
struct Bretzel5Value {
  double f = 0;
  glm::dvec3 gradient{0.0};
  glm::dmat3 hessian{0.0};
};
Bretzel5Value bretzel5(const glm::dvec3& u);

} // namespace dtf
