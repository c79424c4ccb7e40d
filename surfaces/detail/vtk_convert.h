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

} // namespace dtf::surfaces::detail
