#include "surfaces/detail/vtk_convert.h"

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTriangleFilter.h>

namespace dtf::surfaces::detail {

vtkSmartPointer<vtkPolyData> toVtk(const Mesh& mesh) {
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(mesh.positions.size()));
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), mesh.positions[i].x, mesh.positions[i].y, mesh.positions[i].z);
  vtkNew<vtkCellArray> tris;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    vtkIdType ids[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    tris->InsertNextCell(3, ids);
  }
  poly->SetPoints(pts);
  poly->SetPolys(tris);
  if (mesh.normals.size() == mesh.positions.size()) {
    vtkNew<vtkFloatArray> n;
    n->SetName("Normals");
    n->SetNumberOfComponents(3);
    n->SetNumberOfTuples(static_cast<vtkIdType>(mesh.normals.size()));
    for (std::size_t i = 0; i < mesh.normals.size(); ++i)
      n->SetTuple3(static_cast<vtkIdType>(i), mesh.normals[i].x, mesh.normals[i].y, mesh.normals[i].z);
    poly->GetPointData()->SetNormals(n);
  }
  return poly;
}

Mesh fromVtk(vtkPolyData* input) {
  Mesh m;
  if (!input || !input->GetPoints()) return m;
  vtkSmartPointer<vtkPolyData> poly = input;
  bool allTriangles = input->GetNumberOfStrips() == 0;
  if (allTriangles && input->GetPolys()) {
    vtkIdType maxCell = input->GetPolys()->GetMaxCellSize();
    allTriangles = maxCell <= 3;
  }
  if (!allTriangles) {
    vtkNew<vtkTriangleFilter> tri;
    tri->SetInputData(input);
    tri->PassVertsOff();
    tri->PassLinesOff();
    tri->Update();
    poly = tri->GetOutput();
  }
  const vtkIdType np = poly->GetNumberOfPoints();
  m.positions.resize(static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    poly->GetPoint(i, p);
    m.positions[static_cast<std::size_t>(i)] = glm::vec3(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = poly->GetPolys();
  if (polys) {
    m.indices.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()) * 3);
    vtkNew<vtkIdList> ids;
    for (polys->InitTraversal(); polys->GetNextCell(ids);) {
      if (ids->GetNumberOfIds() != 3) continue;
      for (int k = 0; k < 3; ++k) m.indices.push_back(static_cast<std::uint32_t>(ids->GetId(k)));
    }
  }
  vtkDataArray* normals = poly->GetPointData() ? poly->GetPointData()->GetNormals() : nullptr;
  if (normals && normals->GetNumberOfTuples() == np && normals->GetNumberOfComponents() == 3) {
    m.normals.resize(static_cast<std::size_t>(np));
    for (vtkIdType i = 0; i < np; ++i) {
      double n[3];
      normals->GetTuple(i, n);
      glm::vec3 v(n[0], n[1], n[2]);
      float l = glm::length(v);
      m.normals[static_cast<std::size_t>(i)] = l > 0 ? v / l : glm::vec3(0, 0, 1);
    }
  } else if (!m.indices.empty()) {
    m.computeNormals();
  }
  return m;
}

} // namespace dtf::surfaces::detail
