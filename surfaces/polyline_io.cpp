// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/polyline_io.h"

#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/detail/vtk_convert.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

namespace fs = std::filesystem;

namespace dtf::surfaces {

namespace {

bool isVtp(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ".vtp";
}

// The named float copies of a VTK attribute array, for `items` tuples starting at tuple `first`.
void takeArrays(vtkFieldData* data, vtkIdType first, std::size_t items, std::vector<TractValues>& out) {
  if (!data) return;
  for (int a = 0; a < data->GetNumberOfArrays(); ++a) {
    vtkDataArray* arr = vtkDataArray::SafeDownCast(data->GetAbstractArray(a));
    if (!arr || arr->GetNumberOfTuples() < first + static_cast<vtkIdType>(items)) continue;
    const int nc = arr->GetNumberOfComponents();
    TractValues v{arr->GetName() ? arr->GetName() : "array" + std::to_string(a), nc, {}};
    v.values.resize(items * static_cast<std::size_t>(nc));
    for (std::size_t i = 0; i < items; ++i)
      for (int c = 0; c < nc; ++c)
        v.values[i * static_cast<std::size_t>(nc) + static_cast<std::size_t>(c)] =
            static_cast<float>(arr->GetComponent(first + static_cast<vtkIdType>(i), c));
    out.push_back(std::move(v));
  }
}

} // namespace

Polylines readVtkPolylines(const std::string& path, VtkTractInfo* infoOut) {
  std::error_code ec;
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError(path + ": cannot read tract file: " + why);
  VtkTractInfo info;
  vtkSmartPointer<vtkPolyData> poly;
  if (isVtp(path)) {
    {
      std::ifstream in(path);
      std::string head(256, '\0');
      in.read(head.data(), 256);
      head.resize(static_cast<std::size_t>(in.gcount()));
      if (head.find("<VTKFile") == std::string::npos || head.find("PolyData") == std::string::npos)
        throw InputError(path + ": not a VTK XML PolyData (.vtp) file");
    }
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    if (!reader->CanReadFile(path.c_str())) throw InputError(path + ": not a VTK XML PolyData (.vtp) file");
    reader->Update();
    if (reader->GetErrorCode() != 0)
      throw InputError(path + ": VTK could not read the file (corrupt or truncated)");
    poly = reader->GetOutput();
    info.format = "VTK XML PolyData";
  } else {
    std::string first;
    {
      // vtkPolyDataReader reports a wrong header only through its error observer; check the magic first.
      std::ifstream in(path);
      std::getline(in, first);
    }
    if (first.rfind("# vtk DataFile Version", 0) != 0) throw InputError(path + ": not a legacy VTK file");
    info.format = "legacy VTK " + first.substr(std::min<std::size_t>(first.size(), 23));
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    if (!reader->IsFilePolyData()) throw InputError(path + ": not a legacy VTK POLYDATA file");
    detail::checkLegacyVtkPolyData(path);
    reader->Update();
    poly = reader->GetOutput();
  }
  if (!poly) throw InputError(path + ": VTK could not read the file");
  info.vertices = poly->GetNumberOfVerts();
  info.polygons = poly->GetNumberOfPolys();
  info.strips = poly->GetNumberOfStrips();
  vtkCellArray* cells = poly->GetLines();
  const bool noLines = !cells || cells->GetNumberOfCells() == 0;
  if (noLines && poly->GetNumberOfPoints() == 0 && poly->GetNumberOfCells() == 0) {
    // Nothing at all: an empty tractogram, as a .tck or .trk of count 0 is (a filter that kept nothing).
    if (infoOut) *infoOut = info;
    return Polylines{};
  }
  if (noLines) {
    std::string holds = std::to_string(poly->GetNumberOfPoints()) + " points";
    if (info.polygons) holds += ", " + std::to_string(info.polygons) + " polygons";
    if (info.strips) holds += ", " + std::to_string(info.strips) + " triangle strips";
    if (info.vertices) holds += ", " + std::to_string(info.vertices) + " vertex cells";
    throw InputError(path + ": the VTK file holds no lines, so no streamlines (it holds " + holds +
                     (info.polygons || info.strips ? ": a surface mesh" : "") + ")");
  }
  vtkPoints* pts = poly->GetPoints();
  const vtkIdType nPoints = pts ? pts->GetNumberOfPoints() : 0;
  Polylines out;
  out.offsets.reserve(static_cast<std::size_t>(cells->GetNumberOfCells()) + 1);
  out.offsets.push_back(0);
  std::vector<vtkIdType> source; // the VTK point of each output point (lines may share or reorder points)
  source.reserve(static_cast<std::size_t>(cells->GetNumberOfConnectivityIds()));
  auto ids = vtkSmartPointer<vtkIdList>::New();
  cells->InitTraversal();
  while (cells->GetNextCell(ids)) {
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) {
      const vtkIdType id = ids->GetId(i);
      if (id < 0 || id >= nPoints)
        throw InputError(path + ": VTK line refers to point " + std::to_string(id) + " of " +
                         std::to_string(nPoints));
      double p[3];
      pts->GetPoint(id, p);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw InputError(path + ": non-finite coordinate at point " + std::to_string(id));
      out.points.emplace_back(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
      source.push_back(id);
    }
    if (out.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  // Point data follow the points each line uses; cell data of the lines come after the vertex cells.
  std::vector<TractValues> pointArrays;
  takeArrays(poly->GetPointData(), 0, static_cast<std::size_t>(nPoints), pointArrays);
  for (auto& a : pointArrays) {
    TractValues v{a.name, a.components, {}};
    const std::size_t nc = static_cast<std::size_t>(a.components);
    v.values.resize(source.size() * nc);
    for (std::size_t i = 0; i < source.size(); ++i)
      std::copy_n(a.values.begin() + static_cast<long>(static_cast<std::size_t>(source[i]) * nc), nc,
                  v.values.begin() + static_cast<long>(i * nc));
    out.perPoint.push_back(std::move(v));
  }
  takeArrays(poly->GetCellData(), info.vertices, out.lineCount(), out.perLine);
  if (infoOut) *infoOut = info;
  return out;
}

void writeVtkPolylines(const std::string& path, const Polylines& lines) {
  if (const std::string bad = lines.inconsistency(); !bad.empty())
    throw InputError("cannot write " + path + ": inconsistent tracts (" + bad + ")");
  for (const auto& q : lines.points)
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      throw InputError("cannot write " + path + ": a point is not finite");
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(lines.points.size()));
  for (std::size_t i = 0; i < lines.points.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), lines.points[i].x, lines.points[i].y, lines.points[i].z);
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(static_cast<vtkIdType>(lines.lineCount()),
                       static_cast<vtkIdType>(lines.points.size()));
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    cells->InsertNextCell(static_cast<vtkIdType>(lines.offsets[l + 1] - lines.offsets[l]));
    for (std::uint32_t i = lines.offsets[l]; i < lines.offsets[l + 1]; ++i)
      cells->InsertCellPoint(i);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(cells);
  auto attach = [](const std::vector<TractValues>& data, vtkFieldData* to) {
    for (const auto& d : data) {
      vtkNew<vtkFloatArray> arr;
      arr->SetName(d.name.c_str());
      arr->SetNumberOfComponents(d.components);
      arr->SetNumberOfTuples(
          static_cast<vtkIdType>(d.values.size() / static_cast<std::size_t>(d.components)));
      std::copy(d.values.begin(), d.values.end(), arr->GetPointer(0));
      to->AddArray(arr);
    }
  };
  attach(lines.perPoint, poly->GetPointData());
  attach(lines.perLine, poly->GetCellData());
  if (!lines.groups.empty()) {
    std::string g;
    for (const auto& x : lines.groups)
      g += (g.empty() ? "'" : ", '") + x.name + "'";
    logWarning(path + ": a VTK file holds no groups; dropped " + g);
  }

  const std::string ext = isVtp(path) ? ".vtp" : ".vtk";
  auto write = [&](const std::string& temp) {
    if (isVtp(path)) {
      vtkNew<vtkXMLPolyDataWriter> w;
      detail::silence(w);
      w->SetFileName(temp.c_str());
      w->SetInputData(poly);
      w->SetDataModeToAppended();
      w->EncodeAppendedDataOff();
      return w->Write() == 1 && w->GetErrorCode() == 0;
    }
    vtkNew<vtkPolyDataWriter> w;
    detail::silence(w);
    w->SetFileName(temp.c_str());
    w->SetInputData(poly);
    w->SetFileTypeToBinary();
    w->SetFileVersion(vtkPolyDataWriter::VTK_LEGACY_READER_VERSION_4_2);
    w->SetHeader("dtfabric tracts (world RAS mm)");
    return w->Write() == 1 && w->GetErrorCode() == 0;
  };
  auto whole = [&](const std::string& temp) {
    const Polylines back = readVtkPolylines(temp);
    return back.lineCount() == lines.lineCount() && back.points.size() == lines.points.size();
  };
  detail::writeVerified(path, ext, "cannot write " + path, write, whole);
}

} // namespace dtf::surfaces
