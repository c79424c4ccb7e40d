// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_files.h"

#include "io/model/error.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"
#include "io/formats/tensor_io.h"
#include "surfaces/polyline_io.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace dtf::session {

namespace {
enum class Format { Tck, Trk, Trx, Vtk, Unknown };

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool endsWith(const std::string& s, const char* suffix) {
  const std::string t(suffix);
  return s.size() >= t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
}

Format formatOf(const std::string& path) {
  std::string p = lower(path);
  while (p.size() > 1 && p.back() == '/')
    p.pop_back();
  if (endsWith(p, ".tck")) return Format::Tck;
  if (endsWith(p, ".trk") || endsWith(p, ".trk.gz")) return Format::Trk;
  if (endsWith(p, ".trx")) return Format::Trx;
  if (endsWith(p, ".vtk") || endsWith(p, ".vtp")) return Format::Vtk;
  std::error_code ec;
  if (fs::is_directory(path, ec) && fs::is_regular_file(fs::path(path) / "header.json", ec))
    return Format::Trx;
  return Format::Unknown;
}

std::string affineText(const glm::dmat4& m) {
  std::string s;
  char buf[64];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%s%g", (r || c) ? " " : "", m[c][r]);
      s += buf;
    }
  return s;
}
} // namespace

bool isTractFileName(const std::string& path) {
  return formatOf(path) != Format::Unknown;
}

Polylines readTracts(const std::string& path, TractFileFacts* facts) {
  TractFileFacts f;
  Polylines out;
  switch (formatOf(path)) {
  case Format::Tck: {
    io::TckInfo info;
    out = io::readTck(path, &info);
    f.format = "MRtrix tck (" + info.datatype + ")";
    f.declaredCount = info.declaredCount;
    f.fields.emplace_back("space", "world RAS mm");
    for (const auto& [k, v] : info.fields)
      if (k != "file" && k != "datatype") f.fields.emplace_back(k, v);
    break;
  }
  case Format::Trk: {
    io::TrkInfo info;
    out = io::readTrk(path, &info);
    f.format = "TrackVis v" + std::to_string(info.version) + (info.gzipped ? " (gzip)" : "") +
               (info.bigEndian ? " big-endian" : "");
    f.declaredCount = info.declaredCount > 0 ? info.declaredCount : -1;
    f.grid = Grid::fromAffine(info.dims, info.voxToRasUsed);
    char vs[96];
    std::snprintf(vs, sizeof vs, "%g %g %g", info.voxelSize.x, info.voxelSize.y, info.voxelSize.z);
    f.fields.emplace_back("space", "voxel mm of the stored voxel order (corner at 0), to world RAS mm");
    f.fields.emplace_back("voxel_order", info.voxelOrder);
    f.fields.emplace_back("affine_order", info.affineOrder);
    f.fields.emplace_back("voxel_size", vs);
    f.fields.emplace_back("vox_to_ras",
                          info.voxToRasRecorded ? affineText(info.voxToRas) : "not recorded (identity used)");
    f.fields.emplace_back("voxmm_to_world", affineText(io::trkVoxmmToWorldOf(info)));
    break;
  }
  case Format::Trx: {
    io::TrxInfo info;
    out = io::readTrx(path, &info);
    f.format = info.folder ? "TRX folder" : "TRX zip";
    f.declaredCount = info.nbStreamlines;
    f.grid = Grid::fromAffine(info.dims, info.voxToRas);
    f.fields.emplace_back("space", "world RAS mm (positions as stored)");
    f.fields.emplace_back("positions", info.positionsDtype);
    f.fields.emplace_back("offsets", info.offsetsDtype +
                                         (info.offsetsHaveEnd ? " (with end entry)" : " (no end entry)"));
    f.fields.emplace_back("voxel_to_rasmm", affineText(info.voxToRas));
    if (!info.folder) f.fields.emplace_back("deflated_entries", std::to_string(info.deflatedEntries));
    for (const auto& s : info.skipped)
      f.fields.emplace_back("skipped", s);
    break;
  }
  case Format::Vtk: {
    surfaces::VtkTractInfo info;
    out = surfaces::readVtkPolylines(path, &info);
    f.format = info.format;
    f.fields.emplace_back("space", "world RAS mm");
    break;
  }
  case Format::Unknown:
    throw InputError(path + ": unknown tract file extension (use .tck, .trk, .trk.gz, .trx, .vtk or .vtp)");
  }
  if (const std::string bad = out.inconsistency(); !bad.empty())
    throw InputError(path + ": inconsistent tracts after reading (" + bad + ")");
  if (f.grid && (f.grid->dims.x <= 0 || f.grid->dims.y <= 0 || f.grid->dims.z <= 0)) f.grid.reset();
  if (facts) *facts = std::move(f);
  return out;
}

void writeTracts(const std::string& path, const Polylines& lines, const Grid* reference) {
  switch (formatOf(path)) {
  case Format::Tck:
    return io::writeTck(path, lines);
  case Format::Trk:
    if (!reference)
      throw UsageError("writing " + path + ": a .trk file needs a reference grid (--reference IMAGE)");
    return io::writeTrk(path, lines, *reference);
  case Format::Trx:
    if (!reference)
      throw UsageError("writing " + path + ": a .trx file needs a reference grid (--reference IMAGE)");
    return io::writeTrx(path, lines, *reference);
  case Format::Vtk:
    return surfaces::writeVtkPolylines(path, lines);
  case Format::Unknown:
    break;
  }
  throw InputError("cannot write " + path +
                   ": unknown tract file extension (use .tck, .trk, .trk.gz, .trx, .vtk or .vtp)");
}

Grid referenceGridOf(const std::string& path) {
  if (isTractFileName(path)) {
    TractFileFacts facts;
    readTracts(path, &facts);
    if (!facts.grid) throw InputError(path + ": this tract file records no reference space (use a NIfTI image)");
    return *facts.grid;
  }
  return io::readHeader(path).grid;
}

} // namespace dtf::session
