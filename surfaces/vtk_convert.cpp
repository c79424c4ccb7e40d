// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/detail/vtk_convert.h"

#include "io/model/error.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <unistd.h>
#include <vector>
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTriangleFilter.h>

namespace dtf::surfaces::detail {

namespace {

// Reads the numbers of one data block of a legacy VTK file: whitespace-separated tokens (ASCII) or
// big-endian binary values of `type`, starting at the stream's position.
class LegacyVtkData {
public:
  LegacyVtkData(std::ifstream& in, bool binary, const std::string& path)
      : in_(in), binary_(binary), path_(path) {}

  static int typeSize(const std::string& type) {
    static const std::pair<const char*, int> kSizes[] = {
        {"bit", 0},    {"char", 1},         {"unsigned_char", 1}, {"short", 2},         {"unsigned_short", 2},
        {"int", 4},    {"unsigned_int", 4}, {"long", 8},          {"unsigned_long", 8}, {"float", 4},
        {"double", 8}, {"vtktypeint64", 8}, {"vtktypeuint64", 8}, {"vtkIdType", 8}};
    for (const auto& [name, size] : kSizes)
      if (type == name) return size;
    return -1;
  }

  // Skips `count` values of `type` (a section's data); false where the file ends first.
  bool skip(std::uint64_t count, const std::string& type) {
    if (!binary_) {
      std::string t;
      for (std::uint64_t i = 0; i < count; ++i)
        if (!(in_ >> t)) return false;
      return true;
    }
    const int size = typeSize(type);
    if (size <= 0)
      throw dtf::InputError(path_ + ": a legacy VTK data type '" + type + "' the reader does not take");
    const std::streamoff here = in_.tellg();
    in_.seekg(0, std::ios::end);
    const std::streamoff end = in_.tellg();
    const std::uint64_t bytes = count * static_cast<std::uint64_t>(size);
    if (here < 0 || static_cast<std::uint64_t>(end - here) < bytes) return false;
    in_.seekg(here + static_cast<std::streamoff>(bytes));
    return true;
  }

  // The next integer value of `type` (binary) or token (ASCII); false at the end of the file.
  bool integer(const std::string& type, std::int64_t& v) {
    if (!binary_) {
      std::string t;
      if (!(in_ >> t)) return false;
      char* e = nullptr;
      v = std::strtoll(t.c_str(), &e, 10);
      if (e == t.c_str() || *e != '\0')
        throw dtf::InputError(path_ + ": '" + t + "' where a legacy VTK cell section needs an integer");
      return true;
    }
    const int size = typeSize(type);
    if (size != 4 && size != 8)
      throw dtf::InputError(path_ + ": cell ids of type '" + type +
                            "' (legacy VTK takes int or vtktypeint64)");
    unsigned char b[8];
    if (!in_.read(reinterpret_cast<char*>(b), size)) return false;
    std::uint64_t u = 0;
    for (int i = 0; i < size; ++i)
      u = (u << 8) | b[i];
    v = size == 4 ? static_cast<std::int64_t>(static_cast<std::int32_t>(static_cast<std::uint32_t>(u)))
                  : static_cast<std::int64_t>(u);
    return true;
  }

  // The next non-empty line (a section keyword); false at the end of the file.
  bool line(std::string& out) {
    while (std::getline(in_, out)) {
      while (!out.empty() && (out.back() == '\r' || out.back() == ' ' || out.back() == '\t'))
        out.pop_back();
      const auto first = out.find_first_not_of(" \t");
      if (first == std::string::npos) continue;
      out.erase(0, first);
      return true;
    }
    return false;
  }

  // Skips a METADATA block: its lines up to the first empty one.
  void skipMetadata() {
    std::string l;
    while (std::getline(in_, l)) {
      while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t'))
        l.pop_back();
      if (l.empty()) return;
    }
  }

private:
  std::ifstream& in_;
  bool binary_;
  const std::string& path_;
};

} // namespace

void checkLegacyVtkPolyData(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file");
  std::string magic, title, encoding, dataset;
  std::getline(in, magic);
  std::getline(in, title);
  std::getline(in, encoding);
  while (!encoding.empty() && (encoding.back() == '\r' || encoding.back() == ' '))
    encoding.pop_back();
  const bool binary = encoding == "BINARY";
  if (!binary && encoding != "ASCII")
    throw InputError(path + ": the third line of a legacy VTK file must be ASCII or BINARY, not '" +
                     encoding + "'");
  const double version = std::atof(magic.substr(std::min<std::size_t>(magic.size(), 23)).c_str());
  LegacyVtkData data(in, binary, path);
  if (!data.line(dataset) || dataset.rfind("DATASET POLYDATA", 0) != 0) return; // IsFilePolyData decides
  std::int64_t points = -1;
  const auto fail = [&](const std::string& why) { throw InputError(path + ": " + why); };
  std::string keyword;
  while (data.line(keyword)) {
    std::istringstream head(keyword);
    std::string name;
    head >> name;
    if (name == "METADATA") {
      data.skipMetadata();
      continue;
    }
    if (name == "POINTS") {
      std::string type;
      if (!(head >> points >> type) || points < 0) fail("a malformed POINTS line '" + keyword + "'");
      if (!data.skip(3 * static_cast<std::uint64_t>(points), type))
        fail("POINTS says " + std::to_string(points) +
             " points, but the file ends before their coordinates do");
      continue;
    }
    if (name != "VERTICES" && name != "LINES" && name != "POLYGONS" && name != "TRIANGLE_STRIPS") return;
    std::int64_t cells = -1, size = -1;
    if (!(head >> cells >> size) || cells < 0 || size < 0)
      fail("a malformed " + name + " line '" + keyword + "'");
    if (points < 0) fail(name + " comes before POINTS");
    const auto checkId = [&](std::int64_t id) {
      if (id < 0 || id >= points)
        fail(name + " refers to point " + std::to_string(id) + ", but POINTS holds " +
             std::to_string(points));
    };
    if (version < 5.0) {
      // Legacy layout: `size` integers, each cell its point count followed by its ids.
      std::int64_t read = 0, v = 0;
      for (std::int64_t c = 0; c < cells; ++c) {
        if (read >= size || !data.integer("int", v))
          fail(name + " says " + std::to_string(cells) + " cells in " + std::to_string(size) +
               " numbers, but holds fewer cells");
        ++read;
        if (v < 0 || v > size - read)
          fail(name + " cell " + std::to_string(c) + " claims " + std::to_string(v) + " points" +
               (v < 0 ? std::string(" (a negative count)")
                      : ", more than the " + std::to_string(size) + " numbers the section header allows"));
        for (std::int64_t k = 0; k < v; ++k) {
          std::int64_t id = 0;
          if (!data.integer("int", id)) fail(name + ": the file ends inside cell " + std::to_string(c));
          checkId(id);
        }
        read += v;
      }
      if (read != size)
        fail(name + " says " + std::to_string(size) + " numbers for its " + std::to_string(cells) +
             " cells, but they hold " + std::to_string(read));
      continue;
    }
    // 5.x layout: `cells` offsets (the cell count + 1) and `size` connectivity ids, each block typed.
    std::string block, type;
    std::vector<std::int64_t> offsets;
    if (!data.line(block)) fail(name + ": the file ends before its OFFSETS");
    {
      std::istringstream b(block);
      std::string word;
      b >> word >> type;
      if (word != "OFFSETS") fail(name + " in a version 5 file needs OFFSETS, not '" + block + "'");
    }
    offsets.reserve(static_cast<std::size_t>(std::min<std::int64_t>(cells, 1 << 24)));
    for (std::int64_t i = 0; i < cells; ++i) {
      std::int64_t v = 0;
      if (!data.integer(type, v)) fail(name + ": the file ends inside OFFSETS");
      if (v < 0 || v > size || (!offsets.empty() && v < offsets.back()))
        fail(name + " offset " + std::to_string(i) + " (" + std::to_string(v) +
             ") is negative, decreasing, or beyond the " + std::to_string(size) + " connectivity ids");
      offsets.push_back(v);
    }
    if (!offsets.empty() && (offsets.front() != 0 || offsets.back() != size))
      fail(name + " offsets must run from 0 to the " + std::to_string(size) + " connectivity ids");
    if (!data.line(block)) fail(name + ": the file ends before its CONNECTIVITY");
    {
      std::istringstream b(block);
      std::string word;
      b >> word >> type;
      if (word != "CONNECTIVITY") fail(name + " in a version 5 file needs CONNECTIVITY, not '" + block + "'");
    }
    for (std::int64_t i = 0; i < size; ++i) {
      std::int64_t id = 0;
      if (!data.integer(type, id)) fail(name + ": the file ends inside CONNECTIVITY");
      checkId(id);
    }
  }
}

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
  bool badIndex = false;
  if (polys) {
    const vtkIdType nCells = polys->GetNumberOfCells();
    m.indices.reserve(static_cast<std::size_t>(nCells) * 3);
    // Direct offsets/connectivity access: the per-cell traversal API costs more than the contouring.
    // An index outside [0, np) (a file's negative or too large index) is kept as np, out of range, for the
    // caller's check; the normals are then not computed from it.
    auto copy = [&](const auto* offsets, const auto* conn) {
      for (vtkIdType c = 0; c < nCells; ++c) {
        if (offsets[c + 1] - offsets[c] != 3) continue;
        for (auto k = offsets[c]; k < offsets[c + 1]; ++k) {
          const bool inside = conn[k] >= 0 && static_cast<vtkIdType>(conn[k]) < np;
          badIndex = badIndex || !inside;
          m.indices.push_back(static_cast<std::uint32_t>(inside ? conn[k] : np));
        }
      }
    };
    if (polys->IsStorage64Bit())
      copy(polys->GetOffsetsArray64()->GetPointer(0), polys->GetConnectivityArray64()->GetPointer(0));
    else
      copy(polys->GetOffsetsArray32()->GetPointer(0), polys->GetConnectivityArray32()->GetPointer(0));
  }
  if (badIndex) return m;
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

void silence(vtkAlgorithm* algorithm) {
  vtkNew<vtkCallbackCommand> drop; // no callback: the event is handled, nothing printed
  algorithm->AddObserver(vtkCommand::ErrorEvent, drop);
  algorithm->AddObserver(vtkCommand::WarningEvent, drop);
  algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, drop);
  algorithm->GetExecutive()->AddObserver(vtkCommand::WarningEvent, drop);
}

void writeVerified(const std::string& path, const std::string& ext, const std::string& what,
                   const std::function<bool(const std::string& temp)>& write,
                   const std::function<bool(const std::string& temp)>& readsBackWhole) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(what + ": directory does not exist");
  const std::string temp =
      (dir / ("." + p.filename().string() + ".tmp" + std::to_string(::getpid()) + ext)).string();
  auto fail = [&](const std::string& why) {
    fs::remove(temp, ec);
    throw InputError(what + why);
  };
  bool written = false;
  try {
    written = write(temp);
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
  if (!written || !fs::exists(temp, ec)) fail(": VTK's writer failed (disk full or file size limit?)");
  bool whole = false;
  try {
    whole = readsBackWhole(temp);
  } catch (const InputError&) {
    whole = false; // a reader's complaint about our own file means the write fell short
  }
  if (!whole) fail(": the written file is incomplete (disk full or file size limit?)");
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
    fail(": it exists and is not a regular file (a folder, device or pipe): refusing to replace it");
  fs::rename(temp, path, ec);
  if (ec) fail(": " + ec.message());
}

void keepLargeComponents(Mesh& m, double fraction) {
  const std::size_t nt = m.triangleCount();
  if (nt == 0 || fraction <= 0) return;
  std::vector<std::uint32_t> parent(m.positions.size());
  for (std::size_t i = 0; i < parent.size(); ++i)
    parent[i] = static_cast<std::uint32_t>(i);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
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
  for (std::size_t t = 0; t < nt; ++t)
    largest = std::max(largest, ++count[find(m.indices[3 * t])]);
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
