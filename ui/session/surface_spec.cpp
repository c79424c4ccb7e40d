// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/surface_spec.h"

#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "surfaces/fibre_surface.h"
#include "surfaces/isosurface.h"
#include "surfaces/mesh_io.h"
#include "surfaces/slices.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace dtf::session {

namespace {

std::vector<double> parseNumbers(const std::string& text, std::size_t count, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    char* end = nullptr;
    double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(v))
      throw UsageError(what + ": '" + part + "' is not a number");
    out.push_back(v);
  }
  if (out.size() != count)
    throw UsageError(what + ": expected " + std::to_string(count) + " numbers in '" + text + "'");
  return out;
}

// "X,Y,Z:X,Y,Z" into two points.
void parsePair(const std::string& text, glm::dvec3& a, glm::dvec3& b, const std::string& what) {
  auto colon = text.find(':');
  if (colon == std::string::npos) throw UsageError(what + " needs two points separated by ':' (X,Y,Z:X,Y,Z)");
  auto p = parseNumbers(text.substr(0, colon), 3, what);
  auto q = parseNumbers(text.substr(colon + 1), 3, what);
  a = glm::dvec3(p[0], p[1], p[2]);
  b = glm::dvec3(q[0], q[1], q[2]);
}

ScalarVolume validMask(const TensorField& field) {
  ScalarVolume v(field.grid, 1);
  for (std::size_t i = 0; i < field.valid.size(); ++i)
    v.data[i] = field.valid[i] ? 1.0f : 0.0f;
  return v;
}

} // namespace

namespace {
bool startsWithKind(const std::string& t) {
  for (const char* k :
       {"fa=", "iso=", "slice=", "plane=", "fibre=", "fiber=", "fibre-voxel=", "fiber-voxel=", "mesh="})
    if (t.rfind(k, 0) == 0) return true;
  return false;
}
} // namespace

SurfaceSpec parseSurfaceSpec(const std::string& text) {
  // Split on '+' where the next part starts a new surface (a '+' inside a file name stays).
  std::vector<std::string> pieces;
  std::size_t start = 0;
  for (std::size_t p = text.find('+'); p != std::string::npos; p = text.find('+', p + 1)) {
    if (startsWithKind(text.substr(p + 1))) {
      pieces.push_back(text.substr(start, p - start));
      start = p + 1;
    }
  }
  pieces.push_back(text.substr(start));
  if (pieces.size() > 1) {
    SurfaceSpec c;
    c.kind = SurfaceSpec::Kind::Combined;
    c.text = text;
    for (const auto& piece : pieces)
      c.parts.push_back(parseSurfaceSpec(piece));
    return c;
  }
  SurfaceSpec s;
  s.text = text;
  auto eq = text.find('=');
  if (eq == std::string::npos)
    throw UsageError(
        "surface '" + text +
        "' must look like fa=0.25, slice=axial:20, plane=..., fibre=..., iso=FILE:V or mesh=FILE");
  std::string kind = text.substr(0, eq), rest = text.substr(eq + 1);
  if (kind == "fa") {
    s.kind = SurfaceSpec::Kind::Fa;
    s.value = parseNumbers(rest, 1, "fa threshold")[0];
    if (s.value <= 0 || s.value >= 1) throw UsageError("fa threshold must lie in (0, 1), got " + rest);
  } else if (kind == "iso") {
    s.kind = SurfaceSpec::Kind::Iso;
    auto colon = rest.rfind(':');
    if (colon == std::string::npos) throw UsageError("iso surface needs FILE:VALUE, got '" + rest + "'");
    s.file = rest.substr(0, colon);
    s.value = parseNumbers(rest.substr(colon + 1), 1, "iso value")[0];
  } else if (kind == "slice") {
    s.kind = SurfaceSpec::Kind::Slice;
    auto colon = rest.find(':');
    s.axis = rest.substr(0, colon);
    surfaces::parseSliceAxis(s.axis); // validates
    if (colon != std::string::npos) {
      double idx = parseNumbers(rest.substr(colon + 1), 1, "slice index")[0];
      if (idx != std::floor(idx))
        throw UsageError("slice index must be an integer, got " + rest.substr(colon + 1));
      if (std::abs(idx) > 1e6)
        throw UsageError("slice index " + rest.substr(colon + 1) + " is absurd (beyond 10^6)");
      s.index = static_cast<int>(idx);
      if (s.index < 0) throw UsageError("slice index must not be negative");
    }
  } else if (kind == "plane") {
    s.kind = SurfaceSpec::Kind::Plane;
    parsePair(rest, s.a, s.b, "plane");
    if (glm::length(s.b) == 0) throw UsageError("plane normal must be non-zero");
  } else if (kind == "fibre" || kind == "fiber" || kind == "fibre-voxel" || kind == "fiber-voxel") {
    s.kind = SurfaceSpec::Kind::Fibre;
    s.voxelCoords = kind.find("voxel") != std::string::npos;
    parsePair(rest, s.a, s.b, "fibre seed line");
  } else if (kind == "mesh") {
    s.kind = SurfaceSpec::Kind::Mesh;
    s.file = rest;
    if (rest.empty()) throw UsageError("mesh= needs a file");
  } else {
    throw UsageError("unknown surface kind '" + kind + "' (fa, iso, slice, plane, fibre, fibre-voxel, mesh)");
  }
  return s;
}

std::string describeSurface(const SurfaceSpec& s) {
  std::ostringstream o;
  switch (s.kind) {
  case SurfaceSpec::Kind::Fa:
    o << "FA isosurface at " << s.value;
    break;
  case SurfaceSpec::Kind::Iso:
    o << "isosurface of " << s.file << " at " << s.value;
    break;
  case SurfaceSpec::Kind::Slice:
    o << s.axis << " slice " << (s.index < 0 ? std::string("(middle)") : std::to_string(s.index));
    break;
  case SurfaceSpec::Kind::Plane:
    o << "oblique plane " << s.text.substr(6);
    break;
  case SurfaceSpec::Kind::Fibre:
    o << "fibre-following surface from " << s.text.substr(s.text.find('=') + 1);
    break;
  case SurfaceSpec::Kind::Mesh:
    o << "mesh " << s.file;
    break;
  case SurfaceSpec::Kind::Combined:
    for (std::size_t i = 0; i < s.parts.size(); ++i)
      o << (i ? " + " : "") << describeSurface(s.parts[i]);
    break;
  }
  return o.str();
}

Mesh buildSurface(const SurfaceSpec& s, const TensorField& field, const ScalarVolume& fa,
                  const SurfaceBuildOptions& o) {
  Mesh m;
  switch (s.kind) {
  case SurfaceSpec::Kind::Fa: {
    surfaces::IsosurfaceOptions io;
    io.smoothSigmaVoxels = o.smoothSigmaVoxels;
    io.minComponentFraction = o.minComponentFraction;
    io.meshSmoothIterations = o.meshSmoothIterations;
    io.maxShiftVoxels = o.maxShiftVoxels;
    m = surfaces::extractIsosurface(fa, s.value, io, o.smoothing);
    if (m.empty()) throw InputError("FA threshold " + std::to_string(s.value) + " yields no surface");
    break;
  }
  case SurfaceSpec::Kind::Iso: {
    ScalarVolume v = io::readScalarVolume(s.file);
    surfaces::IsosurfaceOptions io;
    io.minComponentFraction = o.minComponentFraction;
    m = surfaces::extractIsosurface(v, s.value, io);
    if (m.empty())
      throw InputError("iso value " + std::to_string(s.value) + " of " + s.file + " yields no surface");
    break;
  }
  case SurfaceSpec::Kind::Slice: {
    surfaces::SliceAxis axis = surfaces::parseSliceAxis(s.axis);
    int idx = s.index < 0 ? surfaces::sliceCount(field.grid, axis) / 2 : s.index;
    ScalarVolume clip = validMask(field);
    surfaces::SliceOptions so;
    if (o.clipToData) so.clip = &clip;
    so.anyCorner = o.dataEdgeCells;
    m = surfaces::makeSlice(field.grid, axis, idx, so);
    if (m.empty()) throw InputError(describeSurface(s) + " holds no tensor data");
    break;
  }
  case SurfaceSpec::Kind::Plane: {
    ScalarVolume clip = validMask(field);
    surfaces::SliceOptions so;
    if (o.clipToData) so.clip = &clip;
    if (o.dataEdgeCells) {
      so.anyCorner = true;
      so.clipFloor = 0.05f; // the 0.5 contour can pass between samples of the plane's step
    }
    double step = o.planeStepMm > 0
                      ? o.planeStepMm
                      : 0.5 * std::min({field.grid.spacing.x, field.grid.spacing.y, field.grid.spacing.z});
    m = surfaces::makePlane(field.grid, s.a, s.b, step, so);
    if (m.empty()) throw InputError(describeSurface(s) + " misses the tensor data");
    break;
  }
  case SurfaceSpec::Kind::Fibre: {
    glm::dvec3 a = s.voxelCoords ? field.grid.toWorld(s.a) : s.a;
    glm::dvec3 b = s.voxelCoords ? field.grid.toWorld(s.b) : s.b;
    surfaces::FibreSurfaceOptions fo;
    fo.stepMm = o.fibreStepMm;
    fo.maxLengthMm = o.fibreLengthMm;
    fo.faStop = o.fibreFaStop;
    fo.seedSpacingMm = o.fibreSeedSpacingMm;
    m = surfaces::fibreSurfaceFromLine(field, a, b, fo);
    break;
  }
  case SurfaceSpec::Kind::Mesh:
    m = surfaces::readMesh(s.file);
    break;
  case SurfaceSpec::Kind::Combined:
    for (const auto& part : s.parts) {
      Mesh p = buildSurface(part, field, fa, o);
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      if (p.normals.size() != p.positions.size()) p.computeNormals();
      if (m.normals.size() != m.positions.size()) m.computeNormals();
      m.positions.insert(m.positions.end(), p.positions.begin(), p.positions.end());
      m.normals.insert(m.normals.end(), p.normals.begin(), p.normals.end());
      for (auto i : p.indices)
        m.indices.push_back(base + i);
    }
    break;
  }
  return m;
}

} // namespace dtf::session
