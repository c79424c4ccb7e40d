#include "surfaces/detail/vtk_convert.h"

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTriangleFilter.h>

#include <algorithm>
#include <vector>

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
  if (auto* f = vtkFloatArray::FastDownCast(poly->GetPoints()->GetData())) {
    std::copy_n(f->GetPointer(0), 3 * np, &m.positions[0].x);
  } else {
    for (vtkIdType i = 0; i < np; ++i) {
      double p[3];
      poly->GetPoint(i, p);
      m.positions[static_cast<std::size_t>(i)] = glm::vec3(p[0], p[1], p[2]);
    }
  }
  vtkCellArray* polys = poly->GetPolys();
  if (polys) {
    const vtkIdType nCells = polys->GetNumberOfCells();
    m.indices.reserve(static_cast<std::size_t>(nCells) * 3);
    // Direct offsets/connectivity access: the per-cell traversal API costs more than the contouring.
    auto copy = [&](const auto* offsets, const auto* conn) {
      for (vtkIdType c = 0; c < nCells; ++c) {
        if (offsets[c + 1] - offsets[c] != 3) continue;
        for (auto k = offsets[c]; k < offsets[c + 1]; ++k) m.indices.push_back(static_cast<std::uint32_t>(conn[k]));
      }
    };
    if (polys->IsStorage64Bit())
      copy(polys->GetOffsetsArray64()->GetPointer(0), polys->GetConnectivityArray64()->GetPointer(0));
    else
      copy(polys->GetOffsetsArray32()->GetPointer(0), polys->GetConnectivityArray32()->GetPointer(0));
  }
  vtkDataArray* normals = poly->GetPointData() ? poly->GetPointData()->GetNormals() : nullptr;
  if (normals && normals->GetNumberOfTuples() == np && normals->GetNumberOfComponents() == 3) {
    m.normals.resize(static_cast<std::size_t>(np));
    if (auto* f = vtkFloatArray::FastDownCast(normals)) {
      std::copy_n(f->GetPointer(0), 3 * np, &m.normals[0].x);
    } else {
      for (vtkIdType i = 0; i < np; ++i) {
        double n[3];
        normals->GetTuple(i, n);
        m.normals[static_cast<std::size_t>(i)] = glm::vec3(n[0], n[1], n[2]);
      }
    }
    for (auto& n : m.normals) {
      float l = glm::length(n);
      n = l > 0 ? n / l : glm::vec3(0, 0, 1);
    }
  } else if (!m.indices.empty()) {
    m.computeNormals();
  }
  return m;
}

void keepLargeComponents(Mesh& m, double fraction) {
  const std::size_t nt = m.triangleCount();
  if (nt == 0 || fraction <= 0) return;
  std::vector<std::uint32_t> parent(m.positions.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<std::uint32_t>(i);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t t = 0; t < nt; ++t) {
    std::uint32_t a = find(m.indices[3 * t]);
    for (int k = 1; k < 3; ++k) {
      std::uint32_t b = find(m.indices[3 * t + k]);
      if (a != b) parent[b] = a;
    }
  }
  std::vector<std::uint32_t> count(m.positions.size(), 0);
  std::uint32_t largest = 0;
  for (std::size_t t = 0; t < nt; ++t) largest = std::max(largest, ++count[find(m.indices[3 * t])]);
  const double keep = fraction * largest;
  std::vector<std::int64_t> remap(m.positions.size(), -1);
  std::vector<glm::vec3> pos, nrm;
  std::vector<std::uint32_t> idx;
  idx.reserve(m.indices.size());
  const bool hasNormals = m.normals.size() == m.positions.size();
  for (std::size_t t = 0; t < nt; ++t) {
    if (count[find(m.indices[3 * t])] < keep) continue;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t v = m.indices[3 * t + k];
      if (remap[v] < 0) {
        remap[v] = static_cast<std::int64_t>(pos.size());
        pos.push_back(m.positions[v]);
        if (hasNormals) nrm.push_back(m.normals[v]);
      }
      idx.push_back(static_cast<std::uint32_t>(remap[v]));
    }
  }
  m.positions = std::move(pos);
  m.normals = std::move(nrm);
  m.indices = std::move(idx);
}

} // namespace dtf::surfaces::detail
