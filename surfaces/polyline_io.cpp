#include "surfaces/polyline_io.h"

#include "io/model/error.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>

namespace fs = std::filesystem;

namespace dtf::surfaces {

Polylines readVtkPolylines(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": cannot read tract file: no such file");
  {
    // vtkPolyDataReader reports a wrong header only through its error observer; check the magic first.
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    if (first.rfind("# vtk DataFile", 0) != 0) throw InputError(path + ": not a legacy VTK file");
  }
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->IsFilePolyData()) throw InputError(path + ": not a legacy VTK POLYDATA file");
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  vtkCellArray* cells = poly ? poly->GetLines() : nullptr;
  if (!poly || !cells || cells->GetNumberOfCells() == 0)
    throw InputError(path + ": the VTK file holds no LINES (truncated or not polylines)");
  vtkPoints* pts = poly->GetPoints();
  const vtkIdType nPoints = pts ? pts->GetNumberOfPoints() : 0;
  Polylines out;
  out.offsets.push_back(0);
  auto ids = vtkSmartPointer<vtkIdList>::New();
  cells->InitTraversal();
  while (cells->GetNextCell(ids)) {
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) {
      vtkIdType id = ids->GetId(i);
      if (id < 0 || id >= nPoints)
        throw InputError(path + ": VTK line refers to point " + std::to_string(id) + " of " +
                         std::to_string(nPoints));
      double p[3];
      pts->GetPoint(id, p);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw InputError(path + ": non-finite coordinate at point " + std::to_string(id));
      out.points.emplace_back(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    }
    if (out.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  return out;
}

void writeVtkPolylines(const std::string& path, const Polylines& lines) {
  fs::path p(path);
  fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("cannot write " + path + ": directory does not exist");
  for (const auto& q : lines.points)
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      throw InputError("cannot write " + path + ": a point is not finite");
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(lines.points.size()));
  for (std::size_t i = 0; i < lines.points.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), lines.points[i].x, lines.points[i].y, lines.points[i].z);
  vtkNew<vtkCellArray> cells;
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    cells->InsertNextCell(static_cast<vtkIdType>(lines.offsets[l + 1] - lines.offsets[l]));
    for (std::uint32_t i = lines.offsets[l]; i < lines.offsets[l + 1]; ++i)
      cells->InsertCellPoint(i);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(cells);

  const std::string temp =
      (dir / ("." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + ".vtk")).string();
  vtkNew<vtkPolyDataWriter> w;
  w->SetFileName(temp.c_str());
  w->SetInputData(poly);
  w->SetFileTypeToBinary();
  w->SetHeader("dtfabric tracts (world RAS mm)");
  const int ok = w->Write();
  if (!ok || !fs::exists(temp, ec)) {
    fs::remove(temp, ec);
    throw InputError("cannot write " + path);
  }
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw InputError("cannot write " + path + ": " + ec.message());
  }
}

} // namespace dtf::surfaces
