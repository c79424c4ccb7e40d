// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic streamlines for tract tests.
#pragma once

#include "io/model/geometry.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace dtf::test {

// `lines` straight lines of `points` points each: line i holds (k, i, 0) for k = 0 .. points - 1.
inline Polylines gridLines(std::size_t lines, std::size_t points) {
  Polylines l;
  l.offsets = {0};
  for (std::size_t i = 0; i < lines; ++i) {
    for (std::size_t k = 0; k < points; ++k)
      l.points.emplace_back(float(k), float(i), 0.0f);
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  return l;
}

// Twelve straight lines of 61 points through the origin (a fan in world mm, slightly out of the z = 0 plane).
inline Polylines fanLines() {
  Polylines l;
  l.offsets = {0};
  for (int i = 0; i < 12; ++i) {
    const float a = 0.26f * float(i);
    const glm::vec3 d(std::cos(a), std::sin(a), 0.3f * std::sin(2.0f * a));
    for (int k = -30; k <= 30; ++k)
      l.points.push_back(d * float(k));
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  return l;
}

} // namespace dtf::test
