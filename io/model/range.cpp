// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/range.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dtf {

bool Range::contains(double v) const {
  if (!(v >= lo && v <= hi)) return false;
  return !(loOpen && v == lo) && !(hiOpen && v == hi);
}

bool Range::bounded() const {
  return std::isfinite(lo) || std::isfinite(hi);
}

std::string Range::text() const {
  const bool lower = std::isfinite(lo), upper = std::isfinite(hi);
  if (lower && upper)
    return std::string(loOpen ? "(" : "[") + shortestNumber(lo) + ", " + shortestNumber(hi) +
           (hiOpen ? ")" : "]");
  if (lower) return std::string(loOpen ? "> " : ">= ") + shortestNumber(lo);
  if (upper) return std::string(hiOpen ? "< " : "<= ") + shortestNumber(hi);
  return "";
}

// A value that is exactly a float (a float field's default) reads back as that float: "0.15", not
// "0.150000006".
std::string shortestNumber(double v) {
  const bool isFloat = static_cast<double>(static_cast<float>(v)) == v;
  char buf[32];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strchr(buf, 'e') && std::abs(v) >= 1e-4 && std::abs(v) < 1e15) continue; // "90", not "9e+01"
    const double back = std::strtod(buf, nullptr);
    if (back == v || (isFloat && static_cast<float>(back) == static_cast<float>(v))) break;
  }
  return buf;
}

} // namespace dtf
