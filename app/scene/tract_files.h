// Tract files by extension: .tck and .trk through io/tracts.h, legacy .vtk through surfaces/polyline_io.h.
// The dispatcher sits in app because it needs both io and surfaces (surfaces may not include io headers,
// and io does not link VTK). Shared by `dtfabric track`, `dtfabric compare` and the viewer.
#pragma once

#include "io/model/geometry.h"
#include "io/model/grid.h"

#include <string>

namespace dtf::app {

// Reads .tck, .trk or .vtk tracts into world RAS mm. Throws InputError naming the file (also for an
// unknown extension).
Polylines readTracts(const std::string& path);
// Writes by extension, atomically. `reference` is the grid a .trk is written on (required for .trk,
// ignored otherwise). Throws InputError; UsageError for .trk without a reference.
void writeTracts(const std::string& path, const Polylines& lines, const Grid* reference);
// True when the name ends in .tck, .trk or .vtk (case-insensitive).
bool isTractFileName(const std::string& path);

} // namespace dtf::app
