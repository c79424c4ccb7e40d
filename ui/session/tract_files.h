// SPDX-License-Identifier: GPL-3.0-or-later
// Tract files by name: .tck, .trk, .trk.gz through io/formats/tracts.h, .trx (zip or folder) through io/formats/trx.h,
// .vtk/.vtp through surfaces/polyline_io.h. The dispatcher sits in app because it needs both io and
// surfaces (surfaces may not include io headers, and io does not link VTK). Shared by `track`, `compare`,
// `info`, `convert`, `render` and the viewer.
#pragma once

#include "io/model/geometry.h"
#include "io/model/grid.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dtf::session {

// What a tract file's header says besides the streamlines.
struct TractFileFacts {
  std::string format;           // e.g. "TrackVis v2 (gzip)", "TRX zip", "MRtrix tck", "legacy VTK 5.1"
  std::optional<Grid> grid;     // the reference space recorded in the file (.trk, .trx): dims and affine
  long long declaredCount = -1; // the header's streamline count, -1 when it has none
  std::vector<std::pair<std::string, std::string>> fields; // further facts, in a stable order
};

// Reads any supported tract file into world RAS mm with its data and groups. Throws InputError naming the
// file (also for an unknown extension).
Polylines readTracts(const std::string& path, TractFileFacts* facts = nullptr);
// Writes by extension, atomically. `reference` is the grid a .trk/.trk.gz/.trx is written on (required
// there, ignored otherwise). Data the format cannot hold are dropped with a warning. Throws InputError;
// UsageError for .trk/.trx without a reference.
void writeTracts(const std::string& path, const Polylines& lines, const Grid* reference);
// The reference space in `path`: a tract file's recorded grid (.trk, .trx), else an image header. Throws
// InputError naming the file (also for a tract file that records none).
Grid referenceGridOf(const std::string& path);
// True when the name ends in .tck, .trk, .trk.gz, .trx, .vtk or .vtp (case-insensitive), or names a
// TRX folder.
bool isTractFileName(const std::string& path);

} // namespace dtf::session
