// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/trx.h"

#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/formats/zip_archive.h"
#include "io/model/error.h"
#include "io/model/huge_pages.h"
#include "io/model/log.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

static_assert(std::endian::native == std::endian::little, "TRX arrays are read in place as little-endian");

// ---- dtypes
enum class Kind { Float, Signed, Unsigned };
struct Dtype {
  Kind kind;
  int width;
};

bool parseDtype(const std::string& name, Dtype& d) {
  static const std::map<std::string, Dtype> known = {
      {"float16", {Kind::Float, 2}},   {"float32", {Kind::Float, 4}},   {"float64", {Kind::Float, 8}},
      {"int8", {Kind::Signed, 1}},     {"int16", {Kind::Signed, 2}},    {"int32", {Kind::Signed, 4}},
      {"int64", {Kind::Signed, 8}},    {"uint8", {Kind::Unsigned, 1}},  {"uint16", {Kind::Unsigned, 2}},
      {"uint32", {Kind::Unsigned, 4}}, {"uint64", {Kind::Unsigned, 8}}, {"bool", {Kind::Unsigned, 1}}};
  auto it = known.find(name);
  if (it == known.end()) return false;
  d = it->second;
  return true;
}

float halfToFloat(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu;
  if (exp == 0) {
    const float v = std::ldexp(static_cast<float>(mant), -24);
    return sign ? -v : v;
  }
  const std::uint32_t bits =
      exp == 31 ? (sign | 0x7f800000u | (mant << 13)) : (sign | ((exp + 112) << 23) | (mant << 13));
  return std::bit_cast<float>(bits);
}

// Element i of a little-endian typed array, as double.
double element(const char* p, const Dtype& d, std::size_t i) {
  p += i * static_cast<std::size_t>(d.width);
  auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (d.kind) {
  case Kind::Float:
    if (d.width == 2) {
      std::uint16_t h;
      std::memcpy(&h, p, 2);
      return halfToFloat(h);
    }
    return d.width == 4 ? get(float{}) : get(double{});
  case Kind::Signed:
    return d.width == 1   ? get(std::int8_t{})
           : d.width == 2 ? get(std::int16_t{})
           : d.width == 4 ? get(std::int32_t{})
                          : get(std::int64_t{});
  case Kind::Unsigned:
    return d.width == 1   ? get(std::uint8_t{})
           : d.width == 2 ? get(std::uint16_t{})
           : d.width == 4 ? get(std::uint32_t{})
                          : get(std::uint64_t{});
  }
  return 0;
}

// "<name>[.<n>].<dtype>" -> name, components, dtype text.
bool splitArrayName(const std::string& file, std::string& name, int& components, std::string& dtype) {
  const auto dot = file.rfind('.');
  if (dot == std::string::npos || dot == 0) return false;
  dtype = file.substr(dot + 1);
  name = file.substr(0, dot);
  components = 1;
  const auto dot2 = name.rfind('.');
  if (dot2 != std::string::npos && dot2 + 1 < name.size() &&
      std::all_of(name.begin() + static_cast<long>(dot2) + 1, name.end(),
                  [](char c) { return c >= '0' && c <= '9'; })) {
    if (name.size() - dot2 - 1 > 4) return false;
    components = std::stoi(name.substr(dot2 + 1));
    name = name.substr(0, dot2);
  }
  return !name.empty() && components >= 1;
}

// Entry names stay inside the archive/folder: relative, no "..", no backslashes, no empty components.
bool safeEntryName(const std::string& n) {
  if (n.empty() || n.front() == '/' || n.find('\\') != std::string::npos || n.find('\0') != std::string::npos)
    return false;
  std::size_t b = 0;
  while (b <= n.size()) {
    std::size_t e = n.find('/', b);
    if (e == std::string::npos) e = n.size();
    const std::string part = n.substr(b, e - b);
    if (part == ".." || part == "." || (part.empty() && e != n.size())) return false;
    b = e + 1;
  }
  return true;
}

// The arrays of a TRX container, as views into mappings or inflated buffers owned here.
struct Container {
  std::shared_ptr<const ZipReader> zip;
  std::vector<std::shared_ptr<const MappedFile>> files;
  std::vector<std::unique_ptr<std::string>> buffers;
  std::map<std::string, std::string_view> arrays;
  // What keeps each array's bytes mapped (the archive, or the folder's file) where they are the file's own
  // bytes (stored, not inflated): such an array can be used in place.
  std::map<std::string, std::shared_ptr<const void>> mapped;
};

// The entries of a TRX zip archive or folder into `box` (all names checked to stay inside).
void openTrxContainer(const std::string& path, TrxInfo& info, Container& box) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    info.folder = true;
    const fs::path root(path);
    for (auto it = fs::recursive_directory_iterator(root, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const std::string rel = fs::relative(it->path(), root, ec).generic_string();
      if (it->is_symlink(ec))
        throw InputError(path + ": TRX entry '" + rel +
                         "' is a symbolic link (it could point outside the folder)");
      if (it->is_directory(ec)) continue;
      if (!safeEntryName(rel)) throw InputError(path + ": TRX entry '" + rel + "' escapes the folder");
      box.files.push_back(std::make_shared<const MappedFile>(it->path().string()));
      box.arrays[rel] = box.files.back()->bytes();
      box.mapped[rel] = box.files.back();
    }
    if (ec) throw InputError(path + ": cannot list the TRX folder: " + ec.message());
    return;
  }
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError(path + ": cannot read tract file: " + why);
  box.zip = std::make_shared<const ZipReader>(path);
  for (const auto& e : box.zip->entries()) {
    if (!safeEntryName(e.name)) throw InputError(path + ": TRX entry '" + e.name + "' escapes the archive");
    if (e.name.back() == '/') continue; // folder entry
    if (box.arrays.count(e.name)) throw InputError(path + ": TRX entry '" + e.name + "' appears twice");
    box.buffers.push_back(std::make_unique<std::string>());
    box.arrays[e.name] = box.zip->read(e, *box.buffers.back());
    if (e.method != 0)
      ++info.deflatedEntries;
    else
      box.mapped[e.name] = box.zip;
  }
}

// VOXEL_TO_RASMM must be finite with an invertible rotation-scale part (a .trk written from it divides by it).
void checkTrxAffine(const std::string& path, const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) throw InputError(path + ": TRX VOXEL_TO_RASMM is not finite");
  if (!(std::abs(glm::determinant(glm::dmat3(m))) >= 1e-12))
    throw InputError(path + ": TRX VOXEL_TO_RASMM is singular");
}

// header.json: the counts, VOXEL_TO_RASMM and DIMENSIONS into `info`. Any valid JSON is accepted (escapes,
// exponents, whitespace, members in any order); numbers written as 1.2e2 or 120.0 count as integers.
void readTrxHeader(const std::string& path, const Container& box, TrxInfo& info) {
  auto hj = box.arrays.find("header.json");
  if (hj == box.arrays.end()) throw InputError(path + ": TRX has no header.json");
  const nlohmann::ordered_json header = parseJson(hj->second, path + ": bad TRX header.json");
  if (!header.is_object()) throw InputError(path + ": TRX header.json is not a JSON object");
  auto member = [&](const char* key) -> const nlohmann::ordered_json* {
    const auto it = header.find(key);
    return it == header.end() ? nullptr : &*it;
  };
  auto count = [&](const char* key) {
    const auto* v = member(key);
    const double n = v && v->is_number() ? v->get<double>() : -1;
    if (!(n >= 0 && n <= 4e9 && n == std::floor(n)))
      throw InputError(path + ": TRX header.json has no valid " + key);
    return static_cast<long long>(n);
  };
  info.nbStreamlines = count("NB_STREAMLINES");
  info.nbVertices = count("NB_VERTICES");
  if (info.nbVertices >= 0xffffffffLL) throw InputError(path + ": too many points for one tract set");
  if (const auto* a = member("VOXEL_TO_RASMM")) {
    bool ok = a->is_array() && a->size() == 4;
    for (std::size_t r = 0; ok && r < 4; ++r) {
      const auto& row = (*a)[r];
      ok = row.is_array() && row.size() == 4;
      for (std::size_t c = 0; ok && c < 4; ++c) {
        ok = row[c].is_number() && std::isfinite(row[c].get<double>());
        if (ok) info.voxToRas[static_cast<int>(c)][static_cast<int>(r)] = row[c].get<double>();
      }
    }
    if (!ok) throw InputError(path + ": TRX VOXEL_TO_RASMM is not a 4x4 array of numbers");
    checkTrxAffine(path, info.voxToRas);
  } else {
    logWarning(path + ": TRX header.json has no VOXEL_TO_RASMM; assuming the identity");
  }
  if (const auto* d = member("DIMENSIONS")) {
    bool ok = d->is_array() && d->size() == 3;
    for (std::size_t a = 0; ok && a < 3; ++a) {
      const auto& v = (*d)[a];
      ok = v.is_number() && v.get<double>() >= 0 && v.get<double>() < 1e6 &&
           v.get<double>() == std::floor(v.get<double>());
      if (ok) info.dims[static_cast<int>(a)] = static_cast<int>(v.get<double>());
    }
    if (!ok) throw InputError(path + ": TRX DIMENSIONS is not three non-negative integers");
  }
}

// The positions and offsets arrays with their dtypes.
struct TrxCore {
  std::string_view positions, offsets;
  Dtype posType{}, offType{};
  std::shared_ptr<const void> positionsMapped; // set: the positions are the file's own bytes, mapped
};

TrxCore findTrxCore(const std::string& path, const Container& box, TrxInfo& info) {
  TrxCore core;
  for (const auto& [name, bytes] : box.arrays) {
    if (name.rfind("positions.", 0) == 0) {
      std::string base, dt;
      int comps = 0;
      if (!splitArrayName(name, base, comps, dt) || comps != 3 || !parseDtype(dt, core.posType) ||
          core.posType.kind != Kind::Float)
        throw InputError(path + ": TRX positions '" + name + "' must be positions.3.float16|float32|float64");
      if (!core.positions.empty()) throw InputError(path + ": TRX holds two positions arrays");
      core.positions = bytes;
      if (const auto m = box.mapped.find(name); m != box.mapped.end()) core.positionsMapped = m->second;
      info.positionsDtype = dt;
    } else if (name.rfind("offsets.", 0) == 0) {
      const std::string dt = name.substr(8);
      if ((dt != "uint32" && dt != "uint64") || !parseDtype(dt, core.offType))
        throw InputError(path + ": TRX offsets '" + name +
                         "' has an unknown dtype (uint32 or uint64 expected)");
      if (!core.offsets.empty()) throw InputError(path + ": TRX holds two offsets arrays");
      core.offsets = bytes;
      info.offsetsDtype = dt;
    }
  }
  return core;
}

// The array sizes against the header's counts; returns the number of streamlines to read.
std::size_t trxStreamlineCount(const std::string& path, const TrxCore& c, TrxInfo& info, std::size_t& nOff) {
  const std::size_t nSHeader = static_cast<std::size_t>(info.nbStreamlines),
                    nV = static_cast<std::size_t>(info.nbVertices);
  if (c.positions.data() == nullptr && nV > 0) throw InputError(path + ": TRX has no positions array");
  if (c.offsets.data() == nullptr && nSHeader > 0) throw InputError(path + ": TRX has no offsets array");
  if (c.positions.size() != nV * 3 * static_cast<std::size_t>(c.posType.width))
    throw InputError(path + ": TRX positions hold " + std::to_string(c.positions.size()) +
                     " bytes, but NB_VERTICES " + std::to_string(nV) + " needs " +
                     std::to_string(nV * 3 * static_cast<std::size_t>(c.posType.width)));
  const auto width = static_cast<std::size_t>(c.offType.width);
  nOff = width ? c.offsets.size() / width : 0;
  if (width && (c.offsets.size() % width != 0 || (nOff != nSHeader && nOff != nSHeader + 1)))
    throw InputError(path + ": TRX offsets hold " + std::to_string(c.offsets.size()) +
                     " bytes, but NB_STREAMLINES " + std::to_string(nSHeader) + " needs " +
                     std::to_string(nSHeader) + " or " + std::to_string(nSHeader + 1) + " entries");
  std::size_t nS = nSHeader;
  if (nS > 0 && nOff == nS + 1 && element(c.offsets.data(), c.offType, nOff - 1) != static_cast<double>(nV)) {
    // NB_STREAMLINES + 1 entries whose last is not NB_VERTICES: one start per streamline and a header count
    // one short (dpsv.trx from niivue's demos: 460 starts, 460 dps values, NB_STREAMLINES 459). The data
    // arrays below must then agree with the offsets.
    nS = nOff;
    logWarning(path + ": TRX header NB_STREAMLINES " + std::to_string(nSHeader) + " but the offsets hold " +
               std::to_string(nOff) + " streamline starts and no end entry; reading " + std::to_string(nOff) +
               " streamlines");
  }
  info.offsetsHaveEnd = nS > 0 && nOff == nS + 1;
  return nS;
}

// Offsets: start at 0, never decrease, stay within NB_VERTICES; the end entry, if present, is NB_VERTICES.
void readTrxOffsets(const std::string& path, const TrxCore& c, const TrxInfo& info, std::size_t nS,
                    std::size_t nOff, Polylines& out) {
  const auto nV = static_cast<std::size_t>(info.nbVertices);
  out.offsets.resize(nS + 1);
  for (std::size_t i = 0; i < nOff; ++i) {
    const double o = element(c.offsets.data(), c.offType, i);
    if (o > static_cast<double>(nV) || (i > 0 && o < out.offsets[i - 1]) || (i == 0 && o != 0))
      throw InputError(path + ": TRX offsets are inconsistent at entry " + std::to_string(i) + " (" +
                       std::to_string(static_cast<unsigned long long>(o)) + ", NB_VERTICES " +
                       std::to_string(nV) + ")");
    out.offsets[i] = static_cast<std::uint32_t>(o);
  }
  if (info.offsetsHaveEnd && out.offsets[nS] != nV)
    throw InputError(path + ": TRX offsets end at " + std::to_string(out.offsets[nS]) + ", not NB_VERTICES " +
                     std::to_string(nV));
  out.offsets[nS] = static_cast<std::uint32_t>(nV);
  if (nS == 0 && nV > 0) throw InputError(path + ": TRX holds vertices but no streamlines");
}

// Positions: world RAS mm as stored. Float32 stored uncompressed and aligned to 4 bytes is used in place, in
// the file's mapping (a whole-brain tractogram is GBs: no copy, and its pages stay the page cache's); float32
// elsewhere is copied once, other types converted. Either way every position is checked to be finite.
void readTrxPositions(const std::string& path, const TrxCore& c, std::size_t nV, Polylines& out) {
  auto checkFinite = [&](const glm::vec3* p) {
    for (std::size_t i = 0; i < nV; ++i)
      if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z))
        throw InputError(path + ": TRX position " + std::to_string(i) + " is not finite");
  };
  if (c.posType.width == 4 && c.positionsMapped && nV > 0 &&
      reinterpret_cast<std::uintptr_t>(c.positions.data()) % alignof(glm::vec3) == 0) {
    const auto* p = reinterpret_cast<const glm::vec3*>(c.positions.data());
    checkFinite(p);
    out.points = PointArray::view(c.positionsMapped, p, nV);
    return;
  }
  // Huge pages: the spatial index and the selections read the positions at random.
  out.points.reserve(nV);
  adviseHugePages(out.points.data(), nV * sizeof(glm::vec3));
  out.points.resize(nV);
  if (c.posType.width == 4) {
    if (nV) std::memcpy(out.points.data(), c.positions.data(), nV * 12);
  } else {
    for (std::size_t i = 0; i < nV; ++i)
      for (int k = 0; k < 3; ++k)
        out.points[i][k] =
            static_cast<float>(element(c.positions.data(), c.posType, 3 * i + static_cast<std::size_t>(k)));
  }
  checkFinite(out.points.data());
}

// A groups/ entry: one integer streamline index per member.
TractGroup readTrxGroup(const std::string& path, const std::string& name, const std::string& base,
                        std::string_view bytes, const Dtype& d, int comps, std::size_t items,
                        std::size_t nS) {
  if (d.kind == Kind::Float || comps != 1)
    throw InputError(path + ": TRX group '" + name + "' must be one integer index per streamline");
  TractGroup g{base, {}};
  g.lines.resize(items);
  for (std::size_t i = 0; i < items; ++i) {
    const double v = element(bytes.data(), d, i);
    if (v < 0 || v >= static_cast<double>(nS))
      throw InputError(path + ": TRX group '" + base + "' names streamline " +
                       std::to_string(static_cast<long long>(v)) + " of " + std::to_string(nS));
    g.lines[i] = static_cast<std::uint32_t>(v);
  }
  return g;
}

// A dps/, dpv/ or groups/ entry into `out`.
void readTrxDataEntry(const std::string& path, const std::string& name, std::string_view bytes,
                      std::size_t nS, std::size_t nV, Polylines& out) {
  const bool dps = name.rfind("dps/", 0) == 0, grp = name.rfind("groups/", 0) == 0;
  const std::string file = name.substr(name.find('/') + 1);
  std::string base, dt;
  int comps = 1;
  Dtype d{};
  if (file.find('/') != std::string::npos || !splitArrayName(file, base, comps, dt))
    throw InputError(path + ": TRX entry '" + name + "' is not named <name>[.<n>].<dtype>");
  if (!parseDtype(dt, d))
    throw InputError(path + ": TRX entry '" + name + "' has an unknown dtype '" + dt + "'");
  const std::size_t items =
      dps || grp
          ? (grp ? bytes.size() / static_cast<std::size_t>(d.width) / static_cast<std::size_t>(comps) : nS)
          : nV;
  const std::size_t want = items * static_cast<std::size_t>(comps) * static_cast<std::size_t>(d.width);
  if (bytes.size() != want)
    throw InputError(path + ": TRX entry '" + name + "' holds " + std::to_string(bytes.size()) +
                     " bytes, expected " + std::to_string(want) +
                     (grp   ? ""
                      : dps ? " (NB_STREAMLINES x components x dtype)"
                            : " (NB_VERTICES x components x dtype)"));
  if (grp) {
    out.groups.push_back(readTrxGroup(path, name, base, bytes, d, comps, items, nS));
    return;
  }
  TractValues v{base, comps, {}};
  const std::size_t n = items * static_cast<std::size_t>(comps);
  v.values.resize(n);
  if (d.kind == Kind::Float && d.width == 4) {
    if (n) std::memcpy(v.values.data(), bytes.data(), n * 4);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      v.values[i] = static_cast<float>(element(bytes.data(), d, i));
  }
  (dps ? out.perLine : out.perPoint).push_back(std::move(v));
}

} // namespace

Polylines readTrx(const std::string& path, TrxInfo* infoOut) {
  TrxInfo info;
  Container box;
  openTrxContainer(path, info, box);
  readTrxHeader(path, box, info);
  const TrxCore core = findTrxCore(path, box, info);
  std::size_t nOff = 0;
  const std::size_t nS = trxStreamlineCount(path, core, info, nOff);
  const auto nV = static_cast<std::size_t>(info.nbVertices);
  Polylines out;
  readTrxOffsets(path, core, info, nS, nOff, out);
  readTrxPositions(path, core, nV, out);
  // dps/, dpv/, groups/
  for (const auto& [name, bytes] : box.arrays) {
    if (name.rfind("dps/", 0) == 0 || name.rfind("dpv/", 0) == 0 || name.rfind("groups/", 0) == 0)
      readTrxDataEntry(path, name, bytes, nS, nV, out);
    else if (name != "header.json" && name.rfind("positions.", 0) != 0 && name.rfind("offsets.", 0) != 0)
      info.skipped.push_back(name);
  }
  if (!info.skipped.empty()) {
    std::string s;
    for (const auto& n : info.skipped)
      s += (s.empty() ? "'" : ", '") + n + "'";
    logWarning(path + ": TRX entries not read (data per group and unknown names): " + s);
  }
  if (infoOut) *infoOut = std::move(info);
  return out;
}

void writeTrx(const std::string& path, const Polylines& lines, const Grid& reference) {
  if (const std::string bad = lines.inconsistency(); !bad.empty())
    throw InputError("cannot write " + path + ": inconsistent tracts (" + bad + ")");
  for (std::size_t i = 0; i < lines.points.size(); ++i) {
    const glm::vec3& p = lines.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("cannot write " + path + ": point " + std::to_string(i) + " is not finite");
  }
  nlohmann::ordered_json affine = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r)
    affine.push_back({reference.voxelToWorld[0][r], reference.voxelToWorld[1][r], reference.voxelToWorld[2][r],
                      reference.voxelToWorld[3][r]});
  const nlohmann::ordered_json h = {{"VOXEL_TO_RASMM", affine},
                                    {"DIMENSIONS", {reference.dims.x, reference.dims.y, reference.dims.z}},
                                    {"NB_VERTICES", lines.points.size()},
                                    {"NB_STREAMLINES", lines.lineCount()}};
  const std::string header = jsonText(h);

  AtomicOutput out(path);
  {
    std::ofstream f(out.tempPath(), std::ios::binary | std::ios::trunc);
    if (!f) throw InputError("cannot write " + path + ": cannot create a temporary file");
    ZipWriter zip(f, path);
    zip.add("header.json", header.data(), header.size());
    zip.add("positions.3.float32", lines.points.data(), lines.points.size() * sizeof(glm::vec3));
    const std::vector<std::uint32_t> offsets =
        lines.offsets.empty() ? std::vector<std::uint32_t>{0} : lines.offsets;
    zip.add("offsets.uint32", offsets.data(), offsets.size() * 4);
    auto arrays = [&](const std::vector<TractValues>& data, const char* folder) {
      for (const auto& d : data) {
        if (!safeEntryName(d.name) || d.name.find('/') != std::string::npos) {
          logWarning(path + ": data name '" + d.name + "' cannot be a TRX entry name; dropped");
          continue;
        }
        const std::string comps = d.components > 1 ? "." + std::to_string(d.components) : "";
        zip.add(std::string(folder) + d.name + comps + ".float32", d.values.data(), d.values.size() * 4);
      }
    };
    arrays(lines.perLine, "dps/");
    arrays(lines.perPoint, "dpv/");
    for (const auto& g : lines.groups) {
      if (!safeEntryName(g.name) || g.name.find('/') != std::string::npos) {
        logWarning(path + ": group name '" + g.name + "' cannot be a TRX entry name; dropped");
        continue;
      }
      zip.add("groups/" + g.name + ".uint32", g.lines.data(), g.lines.size() * 4);
    }
    zip.finish();
  }
  out.commit();
}

} // namespace dtf::io
