// SPDX-License-Identifier: GPL-3.0-or-later
// VTK polylines in and out through VTK's own readers and writers: legacy .vtk (4.x and 5.1 POLYDATA) and
// XML .vtp, beside .tck/.trk/.trx (io/formats/tracts.h, io/formats/trx.h). It lives in surfaces because io does not link
// VTK. Coordinates are world RAS mm, as written by MRtrix `tckconvert`, DIPY and ParaView. Point data
// arrays are per-point tract data, cell data arrays of the line cells per-streamline data.
#pragma once

#include "io/model/geometry.h"

#include <string>

namespace dtf::surfaces {

struct VtkTractInfo {
  std::string format; // "legacy VTK 4.2" (version as in the file) or "VTK XML PolyData"
  long long vertices = 0, polygons = 0, strips = 0; // other cells, not read as tracts
};

// Reads the LINES cells of a legacy .vtk or XML .vtp POLYDATA file (chosen by extension). Throws
// InputError naming the file when it is missing, not POLYDATA, holds no lines (saying what it holds
// instead), or has non-finite or out-of-range points.
Polylines readVtkPolylines(const std::string& path, VtkTractInfo* info = nullptr);
// Writes one line cell per polyline atomically: binary legacy 4.2 for .vtk (readable by VTK 5 to 9,
// MRtrix and ParaView), appended-binary XML for .vtp. Per-point and per-streamline data become float
// point and cell data arrays; groups are dropped with a warning. Throws InputError.
void writeVtkPolylines(const std::string& path, const Polylines& lines);

} // namespace dtf::surfaces
