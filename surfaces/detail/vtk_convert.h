// Conversions between dtf::Mesh and vtkPolyData. Private to the surfaces module (VTK stays out of public
// headers): include only from surfaces/*.cpp.
#pragma once

#include "io/model/geometry.h"

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <string>

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

} // namespace dtf::surfaces::detail
