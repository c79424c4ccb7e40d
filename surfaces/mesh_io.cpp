// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/mesh_io.h"

#include "io/model/error.h"
#include "surfaces/detail/vtk_convert.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <vtkAlgorithm.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOBJWriter.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPolyDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

namespace fs = std::filesystem;

namespace dtf::surfaces {

namespace {
std::string lowerExt(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}
} // namespace

Mesh readMesh(const std::string& path) {
  std::error_code ec;
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError("cannot read mesh " + path + ": " + why);
  std::string ext = lowerExt(path);
  vtkSmartPointer<vtkPolyData> poly;
  auto run = [&](auto reader) {
    reader->SetFileName(path.c_str());
    reader->Update();
    poly = reader->GetOutput();
  };
  if (ext == ".ply") {
    detail::checkPly(path);
    run(vtkSmartPointer<vtkPLYReader>::New());
  } else if (ext == ".obj") {
    detail::checkObj(path);
    run(vtkSmartPointer<vtkOBJReader>::New());
  } else if (ext == ".vtp") {
    run(vtkSmartPointer<vtkXMLPolyDataReader>::New());
  } else if (ext == ".vtk") {
    auto r = vtkSmartPointer<vtkPolyDataReader>::New();
    r->SetFileName(path.c_str());
    if (!r->IsFilePolyData())
      throw InputError("cannot read mesh " + path + ": not a legacy VTK POLYDATA file");
    detail::checkLegacyVtkPolyData(path);
    r->Update();
    poly = r->GetOutput();
  } else {
    throw InputError("cannot read mesh " + path + ": unknown extension (use .ply, .obj, .vtk or .vtp)");
  }
  Mesh m = detail::fromVtk(poly);
  if (m.empty()) throw InputError("cannot read mesh " + path + ": the file holds no triangles");
  for (auto i : m.indices)
    if (i >= m.positions.size())
      throw InputError("cannot read mesh " + path +
                       ": a triangle's vertex index is out of range (negative, or " + "not below the " +
                       std::to_string(m.positions.size()) + " vertices)");
  for (const auto& p : m.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("cannot read mesh " + path + ": a vertex position is not finite (NaN or Inf)");
  return m;
}

void writeMesh(const std::string& path, const Mesh& mesh) {
  const std::string ext = lowerExt(path);
  if (ext != ".ply" && ext != ".vtp" && ext != ".obj")
    throw InputError("cannot write mesh " + path + ": unknown extension (use .ply, .vtp or .obj)");
  auto poly = detail::toVtk(mesh);
  auto write = [&](const std::string& temp) {
    auto run = [&](auto w) {
      detail::silence(w);
      w->SetFileName(temp.c_str());
      w->SetInputData(poly);
      return w->Write() == 1 && w->GetErrorCode() == 0;
    };
    if (ext == ".ply") {
      vtkNew<vtkPLYWriter> w;
      w->SetFileTypeToBinary();
      return run(w.Get());
    }
    if (ext == ".vtp") return run(vtkNew<vtkXMLPolyDataWriter>().Get());
    return run(vtkNew<vtkOBJWriter>().Get());
  };
  // Every triangle reads back (each format writes its faces last).
  auto whole = [&](const std::string& temp) {
    return readMesh(temp).triangleCount() == mesh.triangleCount();
  };
  detail::writeVerified(path, ext, "cannot write mesh " + path, write, whole);
}

} // namespace dtf::surfaces
