// SPDX-License-Identifier: GPL-3.0-or-later
// An interval of real numbers, closed, open or half-open; an infinite bound is no bound. The one range type
// of the option tables (command flags, fabric parameters, tracking parameters) and the panels' sliders.
#pragma once

#include <limits>
#include <string>

namespace dtf {

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false; // (lo, ...] or [..., hi)

  static constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static constexpr Range atLeast(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), false, false};
  }
  static constexpr Range above(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), true, false};
  }

  bool contains(double v) const; // false for NaN
  bool bounded() const;          // either bound finite
  // "[1, 90]", "(0, 1]", ">= 0", "> 0", "<= 5"; "" without bounds.
  std::string text() const;
};

// The shortest decimal text that reads back as `v` (as a float when `v` is one): "90", "0.1", "1e-06".
std::string shortestNumber(double v);

} // namespace dtf
