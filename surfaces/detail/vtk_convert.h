// Conversions between dtf::Mesh and vtkPolyData. Private to the surfaces module (VTK stays out of public
// headers): include only from surfaces/*.cpp.
#pragma once

#include "io/model/geometry.h"

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

} // namespace dtf::surfaces::detail
