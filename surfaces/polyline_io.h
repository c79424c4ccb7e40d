// Legacy VTK polylines (POLYDATA with LINES) in and out, the third tract format beside .tck and .trk
// (io/tracts.h). It lives in surfaces because io does not link VTK. Coordinates are world RAS mm, as
// written by MRtrix `tckconvert` and read by ParaView.
#pragma once

#include "io/model/geometry.h"

#include <string>

namespace dtf::surfaces {

// Reads the LINES cells of a legacy .vtk POLYDATA file (other cells are ignored). Throws InputError naming
// the file when it is missing, not POLYDATA, holds no lines, or has non-finite or out-of-range points.
Polylines readVtkPolylines(const std::string& path);
// Writes a binary legacy .vtk POLYDATA file with one LINES cell per polyline, atomically (temporary file
// renamed into place). Throws InputError.
void writeVtkPolylines(const std::string& path, const Polylines& lines);

} // namespace dtf::surfaces
