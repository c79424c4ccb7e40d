// SPDX-License-Identifier: GPL-3.0-or-later
// Tract display choices shared by `render --tracts` (and meant for the viewer): show only some groups, and
// colour by a per-point or per-streamline value through the tract colour map instead of DEC.
#pragma once

#include "io/model/geometry.h"

#include <cstdint>
#include <memory>
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

// Throws as applyTractColouring does for a group or value that `lines` do not hold, without touching their
// points: the check the viewer makes at once when the colouring itself runs off the UI thread.
void checkTractColouring(const Polylines& lines, const TractColouring& c, const std::string& path);

// Keeps the chosen groups' streamlines (each once, in file order) and, when a value is chosen, adds the
// per-point display colours (render/tract_renderer.h) of that value (kNodeColouring: of the node index).
// Throws InputError naming `path` and the names available when a group or value does not exist, UsageError
// for an empty range.
TractColouringApplied applyTractColouring(Polylines& lines, const TractColouring& c, const std::string& path);

// The viewer makes a choice at once up to this many points of the tracts to copy, on its tract worker past
// it (a copy with colours costs about 10 ms per million points, the profile's nodes more).
inline constexpr std::size_t kTractChoiceSyncPoints = 2'000'000;

// The viewer's choice of what its tracts show (ViewerSession): `base` (the loaded tracts, or the ROI
// selection's display subset when the others are hidden) with the ROI selection dimmed, each point's node
// along the profiled streamlines added, the groups kept and the colouring applied.
struct TractChoice {
  std::shared_ptr<const Polylines> base;
  // The ROI selection: with `dim`, indices into base of the streamlines kept lit (the others are drawn grey);
  // with `nodes` and no dim, base is the selection itself.
  std::shared_ptr<const std::vector<std::uint32_t>> roiLines;
  bool roi = false, dim = false;
  bool nodes = false;      // add render::kTractDisplayNode (the Profile panel, or the colouring by profile)
  bool byProfile = false;  // colouring by the profile's value: the nodes carry it, no colour here
  bool noGroups = false;   // the group choice shows none
  TractColouring colouring; // groups (empty: all) and value (empty: DEC)
  std::string path;         // the tracts' file, for messages
  // Work to do beyond sharing `base` as it is.
  bool copies() const { return !colouring.value.empty() || !colouring.groups.empty() || noGroups || dim || nodes; }
};
struct ShownTracts {
  std::shared_ptr<const Polylines> lines;
  TractColouringApplied applied;
};
// Makes what `choice` shows (a copy of base when copies(), else base itself). Throws as
// applyTractColouring.
ShownTracts prepareShownTracts(const TractChoice& choice);

// Warns (naming `path`) when `lines` carry data named `name`, a reserved colouring value that shadows it.
void shadowReservedName(const Polylines& lines, const std::string& name, const std::string& path);

// "LO,HI" -> range; UsageError otherwise.
std::pair<double, double> parseTractRange(const std::string& text);

} // namespace dtf::session
