// SPDX-License-Identifier: GPL-3.0-or-later
// Tract display choices shared by `render --tracts` (and meant for the viewer): show only some groups, and
// colour by a per-point or per-streamline value through the tract colour map instead of DEC.
#pragma once

#include "io/model/geometry.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dtf::session {

// The colouring value that is no data name: each point's node index along the oriented bundle, as
// `dtfabric profile` orients and resamples it (surfaces::nodePerPoint, 100 nodes), from 0 at the start to 99.
// A file's own data named so is not shown (a warning says so).
inline constexpr const char* kNodeColouring = "node";
// The colouring value of the viewer's Profile panel: each point takes the profile's value (e.g. FA) at its
// node, through the same colour map. A file's own data named so is not shown either; `render` has no
// profile and refuses it.
inline constexpr const char* kProfileColouring = "profile";

struct TractColouring {
  std::vector<std::string> groups;                // empty: all streamlines
  std::string value;                              // data name; empty: DEC colours
  std::optional<std::pair<double, double>> range; // colour map range; default: the value's min..max
};

struct TractColouringApplied {
  bool coloured = false;
  double lo = 0, hi = 0; // the range mapped to the ends of the colour map
  std::string summary;   // e.g. "coloured by 'fa' 0.12 .. 0.85 (viridis)"
};

// Keeps the chosen groups' streamlines (each once, in file order) and, when a value is chosen, adds the
// per-point display colours (render/tract_renderer.h) of that value (kNodeColouring: of the node index).
// Throws InputError naming `path` and the names available when a group or value does not exist, UsageError
// for an empty range.
TractColouringApplied applyTractColouring(Polylines& lines, const TractColouring& c, const std::string& path);

// Warns (naming `path`) when `lines` carry data named `name`, a reserved colouring value that shadows it.
void shadowReservedName(const Polylines& lines, const std::string& name, const std::string& path);

// "LO,HI" -> range; UsageError otherwise.
std::pair<double, double> parseTractRange(const std::string& text);

} // namespace dtf::session
