// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/implicit_functions.h"

namespace dtf {

Bretzel5Value bretzel5(const glm::dvec3& u) {
  double x = u.x, y = u.y, z = u.z;
  double a = x * x + 0.25 * y * y - 1, b = 0.25 * x * x + y * y - 1;
  double g = a * b;
  double gx = 2 * x * b + 0.5 * x * a, gy = 0.5 * y * b + 2 * y * a;
  double gxx = 2 * b + 0.5 * a + 2 * x * x, gyy = 0.5 * b + 2 * a + 2 * y * y, gxy = 4.25 * x * y;
  Bretzel5Value v;
  v.f = g * g + z * z - 0.1;
  v.gradient = {2 * g * gx, 2 * g * gy, 2 * z};
  glm::dmat3 h(0.0);
  h[0][0] = 2 * (gx * gx + g * gxx);
  h[1][1] = 2 * (gy * gy + g * gyy);
  h[0][1] = h[1][0] = 2 * (gx * gy + g * gxy);
  h[2][2] = 2;
  v.hessian = h;
  return v;
}

} // namespace dtf
