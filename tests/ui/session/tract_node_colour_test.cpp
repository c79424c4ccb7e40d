// SPDX-License-Identifier: GPL-3.0-or-later
// `--tracts-color node` / the script's `tracts-color node`: each point coloured by its node index along the
// bundle as `dtfabric profile` orients and resamples it. On a bundle of straight lines, half of them stored
// backwards: every oriented streamline's first point takes the colour map's low end and its last point the
// high end, whichever way it was stored; a point at a known arc-length fraction takes its node's colour.
#include "io/model/error.h"
#include "render/tract_renderer.h"
#include "surfaces/analyses/tract_profile.h"
#include "ui/session/tract_colouring.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace dtf;

namespace {

// Eight lines from z = -40 to z = 40 at x = 0..7 mm, unevenly spaced points (quadratic in the index); the odd
// ones stored from z = 40 down.
Polylines bundle() {
  Polylines l;
  l.offsets = {0};
  for (int s = 0; s < 8; ++s) {
    for (int i = 0; i <= 20; ++i) {
      const double t = std::pow(i / 20.0, 2.0);
      const double z = s % 2 ? 40.0 - 80.0 * t : -40.0 + 80.0 * t;
      l.points.emplace_back(float(s), 0.0f, float(z));
    }
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  return l;
}

void expectColour(const Polylines& l, std::size_t point, const glm::vec3& want) {
  const TractValues& c = l.perPoint.back();
  ASSERT_EQ(c.name, render::kTractDisplayColours);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(c.values[4 * point + k], want[k], 1e-6) << "point " << point;
  EXPECT_EQ(c.values[4 * point + 3], 1.0f);
}

} // namespace

TEST(TractNodeColour, TheOrientedFirstAndLastPointsTakeTheColourMapsEnds) {
  Polylines l = bundle();
  // The profile engine's orientation: the first streamline (stored upwards) is the reference.
  const std::vector<float> nodes = surfaces::nodePerPoint(l, nullptr, surfaces::ProfileOptions{});
  ASSERT_EQ(nodes.size(), l.points.size());
  session::TractColouring c;
  c.value = session::kNodeColouring;
  const session::TractColouringApplied a = session::applyTractColouring(l, c, "bundle.tck");
  ASSERT_TRUE(a.coloured);
  EXPECT_EQ(a.lo, 0.0);
  EXPECT_EQ(a.hi, 99.0);
  for (int s = 0; s < 8; ++s) {
    const std::size_t b = l.offsets[s], e = l.offsets[s + 1] - 1;
    const std::size_t bottom = s % 2 ? e : b, top = s % 2 ? b : e; // z = -40 and z = 40
    EXPECT_EQ(nodes[bottom], 0.0f) << s;
    EXPECT_EQ(nodes[top], 99.0f) << s;
    expectColour(l, bottom, render::tractValueColour(0.0f));
    expectColour(l, top, render::tractValueColour(1.0f));
    // Point i of 20 lies at arc-length fraction (i / 20)^2 from its stored start: i = 10 at 1/4, node
    // round(99 / 4) = 25 upwards, round(99 * 3 / 4) = 74 on a line stored downwards.
    EXPECT_EQ(nodes[b + 10], s % 2 ? 74.0f : 25.0f) << s;
    expectColour(l, b + 10, render::tractValueColour(nodes[b + 10] / 99.0f));
  }
  EXPECT_NE(render::tractValueColour(0.0f), render::tractValueColour(1.0f));
}

TEST(TractNodeColour, AStartPointOrientsTheBundleAndShortLinesStayUncoloured) {
  Polylines l = bundle();
  l.points.emplace_back(1.0f, 1.0f, 1.0f); // a one-point streamline: not profiled
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  surfaces::ProfileOptions o;
  o.start = glm::dvec3(0.0, 0.0, 60.0); // start at the top
  const std::vector<float> nodes = surfaces::nodePerPoint(l, nullptr, o);
  for (int s = 0; s < 8; ++s) {
    const std::size_t b = l.offsets[s], e = l.offsets[s + 1] - 1;
    EXPECT_EQ(nodes[s % 2 ? b : e], 0.0f) << s; // z = 40
    EXPECT_EQ(nodes[s % 2 ? e : b], 99.0f) << s;
  }
  EXPECT_TRUE(std::isnan(nodes.back()));
  const std::vector<std::uint32_t> which = {9};
  EXPECT_THROW(surfaces::nodePerPoint(l, &which, o), InputError);
}
