// SPDX-License-Identifier: GPL-3.0-or-later
// Conversions between dtf::Mesh and vtkPolyData. Private to the surfaces module (VTK stays out of public
// headers): include only from surfaces/*.cpp.
#pragma once

#include "io/model/geometry.h"

#include <functional>
#include <string>
#include <vtkAlgorithm.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

namespace dtf::surfaces::detail {

vtkSmartPointer<vtkPolyData> toVtk(const Mesh& mesh);
// Triangles only (other cells are triangulated first); copies point normals when present.
Mesh fromVtk(vtkPolyData* poly);

// Keeps the connected components (triangles sharing vertices) with at least `fraction` of the largest
// one's triangle count and drops unused vertices. Union-find: vtkPolyDataConnectivityFilter takes about
// a second on a 500k-triangle FA surface, this a few milliseconds.
void keepLargeComponents(Mesh& mesh, double fraction);

// Checks the geometry and cell sections of a legacy VTK POLYDATA file (ASCII or binary, the legacy cell
// layout of versions before 5 and the OFFSETS/CONNECTIVITY layout of 5.x) before VTK's reader sees it:
// POINTS holds its n points; every cell section holds exactly the cells and sizes its header says, each
// with point ids in [0, n). vtkPolyDataReader trusts these counts (a cell claiming 10^8 points reads past
// its buffer). Stops at the first attribute section (POINT_DATA, CELL_DATA, FIELD, ...). Throws InputError
// naming `path` and the inconsistency.
void checkLegacyVtkPolyData(const std::string& path);

// Checks a PLY file (ASCII, binary little- or big-endian) before vtkPLYReader sees it: a well-formed header
// and every record its elements declare present, list lengths non-negative. vtkPLYReader reads past the end
// of a short binary file (heap corruption). Throws InputError naming `path` and the problem.
void checkPly(const std::string& path);

// Checks an OBJ file's vertex lines ("v X Y Z [W]") before vtkOBJReader, which reads a coordinate it cannot
// parse ("nan", "inf", "1e400") as 0: three finite numbers each. Throws InputError naming the line.
void checkObj(const std::string& path);

// Sends `algorithm`'s and its executive's error and warning messages to an observer that drops them instead
// of stderr: a failing writer prints its pipeline's whole state, and writeVerified says what failed. No
// global state (vtkObject::GlobalWarningDisplay is shared by every thread).
void silence(vtkAlgorithm* algorithm);

// Writes an output atomically and checks it: `write` writes a temporary file beside `path` (its name ends in
// `ext`, so a reader picks the format from it) and returns false on failure; `readsBackWhole` reads that file
// and says whether it holds everything written. VTK's writers do not report a short write (a full disk, a
// file size limit), so reading back is the check. Then the temporary file replaces `path` (only a regular
// file: never a folder, device or pipe). Throws InputError starting with `what` ("cannot write mesh X");
// no temporary file outlives a failure.
void writeVerified(const std::string& path, const std::string& ext, const std::string& what,
                   const std::function<bool(const std::string& temp)>& write,
                   const std::function<bool(const std::string& temp)>& readsBackWhole);

} // namespace dtf::surfaces::detail
