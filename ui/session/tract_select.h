// SPDX-License-Identifier: GPL-3.0-or-later
// ROI selection of tract files, as `dtfabric select` and dtfabric.select (Python) run it: read the inputs,
// select with the region set (surfaces/selection), write the kept streamlines with every value and group.
// .tck inputs written to a .tck output never enter memory as a whole: they are mapped, selected in place
// and the kept streamlines' bytes copied out (io/formats/mapped_tck.h). Every other combination reads the
// inputs, concatenates them and writes through tract_files.h.
#pragma once

#include "io/model/geometry.h"
#include "io/model/grid.h"
#include "surfaces/selection/regions.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dtf::session {

struct SelectRequest {
  std::vector<std::string> inputs;
  std::string output;
  surfaces::RegionSet regions;
  std::string asGroup;                  // non-empty: a .trx output holds every input streamline and this group
  std::optional<std::string> reference; // the grid of a .trk/.trx output when the inputs record none
  int threads = 0;                      // 0 = all cores
};

struct SelectReport {
  std::size_t streamlines = 0, points = 0; // in the inputs
  std::size_t selected = 0, selectedPoints = 0;
  std::size_t candidates = 0;              // streamlines walked
  bool inPlace = false;                    // the mapped .tck route
  double readSeconds = 0, selectSeconds = 0, writeSeconds = 0;
};

// Checks the request before any work (UsageError: no input, an output that is not a tract file, --as-group
// without a .trx output; InputError: an output that would replace an input). Does not check for an existing
// output (the caller decides about --force).
void checkSelectRequest(const SelectRequest& request);
// Runs a checked request. Throws InputError naming the file for unreadable inputs or unwritable outputs.
SelectReport runSelect(const SelectRequest& request);

// Tract files read and concatenated, with the first recorded reference grid (or `reference`'s).
struct LoadedTracts {
  Polylines lines;
  std::optional<Grid> grid;
};
LoadedTracts readTractInputs(const std::vector<std::string>& inputs, const std::optional<std::string>& reference);
// Writes the streamlines `keep` (ascending) of `in` with their values and groups, or, with `asGroup`, every
// streamline with `keep` added as that group (a .trx output; InputError when the group exists, naming
// `inputName`).
void writeSelection(const std::string& output, LoadedTracts& in, std::vector<std::uint32_t> keep,
                    const std::string& asGroup, const std::string& inputName);

// The inputs concatenated: streamlines in input order; per-point and per-streamline arrays that every input
// holds (same name and components) are kept, others dropped with a warning; groups of the same name are merged.
Polylines concatenateTracts(std::vector<Polylines> parts, const std::vector<std::string>& names);

// The streamlines of `lines` that `set` keeps, ascending (all cores; the index when `indexed`).
std::vector<std::uint32_t> selectIndices(const Polylines& lines, const surfaces::RegionSet& set, bool indexed = false,
                                         int threads = 0);

} // namespace dtf::session
