// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/tracts.h"

#include "io/formats/atomic_file.h"
#include "io/formats/gzip.h"
#include "io/model/error.h"
#include "io/model/huge_pages.h"
#include "io/model/log.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

constexpr std::size_t kTrkHeaderSize = 1000;
constexpr bool kHostLittle = std::endian::native == std::endian::little;

// The whole file; InputError when it cannot be read.
std::string readAll(const std::string& path, const char* what) {
  std::error_code ec;
  if (const std::string why = notARegularFile(path); !why.empty())
    throw InputError(path + ": cannot read " + what + ": " + why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open " + what);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path + ": read error");
  return data;
}

template <typename T> T loadScalar(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

template <typename T> void storeLe(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (!kHostLittle) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

template <typename T> void putLe(char* dst, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (!kHostLittle) std::reverse(b, b + sizeof(T));
  std::memcpy(dst, b, sizeof(T));
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.tempPath(), std::ios::binary | std::ios::trunc);
    if (!f) throw InputError("cannot write " + path + ": cannot create a temporary file");
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.flush();
    if (!f) throw InputError("cannot write " + path + ": write failed (disk full?)");
  }
  out.commit();
}

void checkFinite(const Polylines& lines, const std::string& path) {
  for (std::size_t i = 0; i < lines.points.size(); ++i) {
    const glm::vec3& p = lines.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("cannot write " + path + ": point " + std::to_string(i) + " is not finite");
  }
  if (!lines.offsets.empty() && lines.offsets.back() != lines.points.size())
    throw InputError("cannot write " + path + ": polyline offsets do not match the point count");
}

std::string names(const std::vector<TractValues>& v) {
  std::string s;
  for (const auto& d : v)
    s += (s.empty() ? "'" : ", '") + d.name + "'";
  return s;
}

void warnDropped(const std::string& path, const char* target, const std::vector<TractValues>& perLine,
                 const std::vector<TractValues>& perPoint, const std::vector<TractGroup>& groups) {
  if (!perLine.empty())
    logWarning(path + ": " + target + " holds no per-streamline data; dropped " + names(perLine));
  if (!perPoint.empty())
    logWarning(path + ": " + target + " holds no per-point data; dropped " + names(perPoint));
  if (!groups.empty()) {
    std::string g;
    for (const auto& x : groups)
      g += (g.empty() ? "'" : ", '") + x.name + "'";
    logWarning(path + ": " + target + " holds no groups; dropped " + g);
  }
}

std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

} // namespace

// ---------------------------------------------------------------------------------------------------- .tck

namespace {

// The .tck header lines up to END into info.fields; returns the byte after the END line. Its size is
// bounded by the data offset; runaway headers are refused.
std::size_t parseTckHeader(const std::string& path, std::string_view data, TckInfo& info) {
  std::size_t pos = 0;
  bool first = true, ended = false;
  while (pos < data.size() && pos < (1u << 24)) {
    std::size_t nl = data.find('\n', pos);
    if (nl == std::string::npos) break;
    std::string line = trim(std::string(data.substr(pos, nl - pos)));
    pos = nl + 1;
    if (first) {
      if (line != "mrtrix tracks")
        throw InputError(path + ": not an MRtrix .tck file (no 'mrtrix tracks' line)");
      first = false;
      continue;
    }
    if (line == "END") {
      ended = true;
      break;
    }
    auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    info.fields.emplace_back(trim(line.substr(0, colon)), trim(line.substr(colon + 1)));
  }
  if (first) throw InputError(path + ": not an MRtrix .tck file (no 'mrtrix tracks' line)");
  if (!ended) throw InputError(path + ": .tck header has no END line (truncated header?)");
  return pos;
}

// datatype and count from the fields; returns the 'file' entry.
std::string tckFields(const std::string& path, TckInfo& info) {
  std::string file;
  for (const auto& [k, v] : info.fields) {
    if (k == "datatype")
      info.datatype = v;
    else if (k == "file")
      file = v;
    else if (k == "count") {
      try {
        std::size_t used = 0;
        info.declaredCount = std::stoll(v, &used);
        if (used != v.size() || info.declaredCount < 0) throw std::invalid_argument(v);
      } catch (const std::exception&) {
        throw InputError(path + ": bad .tck count '" + v + "'");
      }
    }
  }
  return file;
}

// Bytes per coordinate (4 or 8) and the byte order from the datatype.
int tckWidth(const std::string& path, const std::string& datatype, bool& big) {
  big = datatype == "Float32BE" || datatype == "Float64BE";
  if (datatype == "Float32LE" || datatype == "Float32BE") return 4;
  if (datatype == "Float64LE" || datatype == "Float64BE") return 8;
  if (datatype.empty()) throw InputError(path + ": .tck header has no datatype");
  throw InputError(path + ": unsupported .tck datatype '" + datatype + "'");
}

// The data offset of "file: . OFFSET", checked against the header's end and the file size.
std::size_t tckDataOffset(const std::string& path, const std::string& file, std::size_t headerEnd,
                          std::size_t size) {
  if (file.empty()) throw InputError(path + ": .tck header has no 'file:' entry");
  std::istringstream ss(file);
  std::string dot;
  long long off = -1;
  ss >> dot >> off;
  if (dot != ".") throw InputError(path + ": .tck data in a separate file ('" + file + "') is not supported");
  if (ss.fail() || off < 0) throw InputError(path + ": bad .tck data offset in 'file: " + file + "'");
  const auto u = static_cast<unsigned long long>(off);
  if (u < headerEnd || u > size)
    throw InputError(path + ": .tck data offset " + std::to_string(off) + " lies " +
                     (u < headerEnd ? "inside the header" : "beyond the end of the file") + " (file size " +
                     std::to_string(size) + " bytes)");
  return static_cast<std::size_t>(off);
}

// The triplets into `out` (NaN triplets separate streamlines); returns whether an Inf triplet ended them.
bool readTckPoints(const std::string& path, const char* base, std::size_t triplets, int width, bool swap,
                   Polylines& out) {
  const std::size_t triplet = 3u * static_cast<std::size_t>(width);
  out.points.reserve(triplets);
  adviseHugePages(out.points.data(), triplets * sizeof(glm::vec3)); // see readTrxPositions
  out.offsets.push_back(0);
  for (std::size_t t = 0; t < triplets; ++t) {
    double v[3];
    for (int c = 0; c < 3; ++c) {
      const char* p = base + t * triplet + static_cast<std::size_t>(c) * width;
      v[c] = width == 4 ? static_cast<double>(loadScalar<float>(p, swap)) : loadScalar<double>(p, swap);
    }
    const int nans = std::isnan(v[0]) + std::isnan(v[1]) + std::isnan(v[2]);
    const int infs = std::isinf(v[0]) + std::isinf(v[1]) + std::isinf(v[2]);
    if (nans == 3) {
      out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
      continue;
    }
    if (infs == 3) return true;
    if (nans || infs)
      throw InputError(path + ": non-finite coordinate in triplet " + std::to_string(t) +
                       " of the .tck data");
    if (std::abs(v[0]) > 1e7 || std::abs(v[1]) > 1e7 || std::abs(v[2]) > 1e7)
      throw InputError(path + ": absurd coordinate in triplet " + std::to_string(t) + " of the .tck data");
    if (out.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    out.points.emplace_back(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  }
  return false;
}

} // namespace

TckInfo readTckHeader(const std::string& path, std::string_view bytes, bool& bigEndian, int& width) {
  TckInfo info;
  const std::size_t headerEnd = parseTckHeader(path, bytes, info);
  const std::string file = tckFields(path, info);
  width = tckWidth(path, info.datatype, bigEndian);
  info.dataOffset = tckDataOffset(path, file, headerEnd, bytes.size());
  return info;
}

Polylines readTck(const std::string& path, TckInfo* infoOut) {
  const std::string data = readAll(path, "tract file");
  TckInfo info;
  const std::size_t headerEnd = parseTckHeader(path, data, info);
  const std::string file = tckFields(path, info);
  bool big = false;
  const int width = tckWidth(path, info.datatype, big);
  info.dataOffset = tckDataOffset(path, file, headerEnd, data.size());

  const std::size_t triplet = 3u * static_cast<std::size_t>(width);
  const std::size_t available = data.size() - info.dataOffset;
  const bool swap = big == kHostLittle;
  Polylines out;
  const bool terminated =
      readTckPoints(path, data.data() + info.dataOffset, available / triplet, width, swap, out);
  if (!terminated) {
    // MATLAB writers end the data with a NaN triplet and no Inf; nibabel reads such files to the end.
    if (available % triplet != 0)
      throw InputError(path + ": truncated .tck data (ends inside a triplet after " +
                       std::to_string(out.offsets.size() - 1) + " streamlines)");
    if (out.offsets.back() != out.points.size())
      throw InputError(path +
                       ": truncated .tck data (no end-of-file marker and the last streamline has no "
                       "NaN separator, after " +
                       std::to_string(out.offsets.size() - 1) + " streamlines)");
    logWarning(path + ": .tck data has no Inf end marker; read to the end of the file");
  }
  if (out.offsets.back() != out.points.size())
    throw InputError(path + ": truncated .tck data (the last streamline has no NaN separator)");
  if (info.declaredCount >= 0 && static_cast<std::size_t>(info.declaredCount) != out.lineCount())
    logWarning(path + ": header count " + std::to_string(info.declaredCount) + " but " +
               std::to_string(out.lineCount()) + " streamlines in the file (stale count; read to the end)");
  if (infoOut) *infoOut = std::move(info);
  return out;
}

void writeTck(const std::string& path, const Polylines& lines) {
  checkFinite(lines, path);
  warnDropped(path, "a .tck file", lines.perLine, lines.perPoint, lines.groups);
  std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: " + std::to_string(lines.lineCount()) +
                     "\ntotal_count: " + std::to_string(lines.lineCount()) + "\nfile: . ";
  // The offset is written with a fixed width so its own length is known; spaces after END align the data to
  // 4 bytes, so readers can use it in place (io/formats/mapped_tck.h).
  const std::size_t offset = (head.size() + 10 + 5 + 3) / 4 * 4; // digits + "\nEND\n" + padding
  char digits[24];
  std::snprintf(digits, sizeof digits, "%-10zu", offset);
  std::string bytes = head + std::string(digits, 10) + "\nEND\n";
  bytes.resize(offset, ' ');
  bytes.reserve(offset + 12 * (lines.points.size() + lines.lineCount() + 1));
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    for (std::uint32_t i = lines.offsets[l]; i < lines.offsets[l + 1]; ++i)
      for (int c = 0; c < 3; ++c)
        storeLe(bytes, lines.points[i][c]);
    for (int c = 0; c < 3; ++c)
      storeLe(bytes, nan);
  }
  for (int c = 0; c < 3; ++c)
    storeLe(bytes, inf);
  writeFileAtomically(path, bytes);
}

// ---------------------------------------------------------------------------------------------------- .trk

namespace {

// Axis codes (e.g. "LPS") -> for each voxel axis the world axis (0..2) and sign; false when not a valid
// permutation of R/L, A/P, S/I.
bool parseAxisCodes(const std::string& order, int axis[3], int sign[3]) {
  if (order.size() != 3) return false;
  bool used[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(order[a])));
    const char* pos = std::strchr("RASLPI", c);
    if (c == 0 || !pos) return false;
    const int k = static_cast<int>(pos - "RASLPI");
    axis[a] = k % 3;
    sign[a] = k < 3 ? 1 : -1;
    if (used[axis[a]]) return false;
    used[axis[a]] = true;
  }
  return true;
}

// Axis codes of an affine: for each voxel axis, the world axis its column points along most.
std::string axisCodesOf(const glm::dmat4& m) {
  std::string code;
  for (int c = 0; c < 3; ++c) {
    int best = 0;
    for (int r = 1; r < 3; ++r)
      if (std::abs(m[c][r]) > std::abs(m[c][best])) best = r;
    code += m[c][best] >= 0 ? "RAS"[best] : "LPI"[best];
  }
  return code;
}

// Splits a TrackVis 20-byte name field as nibabel does: the name up to the first NUL and, when the byte
// after it is a digit, that many values (else 1; an empty field holds none).
std::pair<std::string, int> decodeTrkName(const char* field) {
  const std::size_t n = strnlen(field, 20);
  if (n == 0) return {"", 0};
  int count = 1;
  if (n + 1 < 20 && std::isdigit(static_cast<unsigned char>(field[n + 1]))) {
    count = 0;
    for (std::size_t k = n + 1; k < 20 && std::isdigit(static_cast<unsigned char>(field[k])); ++k)
      count = count * 10 + (field[k] - '0');
  }
  return {std::string(field, n), count};
}

struct TrkSlice {
  std::string name;
  int first = 0, count = 0;
};

// The named slices of `total` values from ten 20-byte name fields; the rest is called `rest`.
std::vector<TrkSlice> trkSlices(const char* fields, int total, const char* rest) {
  std::vector<TrkSlice> out;
  int used = 0;
  for (int f = 0; f < 10 && used < total; ++f) {
    auto [name, count] = decodeTrkName(fields + 20 * f);
    if (count == 0) continue;
    count = std::min(count, total - used);
    out.push_back({name, used, count});
    used += count;
  }
  if (used < total) out.push_back({rest, used, total - used});
  return out;
}

bool isGzip(const std::string& d) {
  return d.size() >= 2 && static_cast<unsigned char>(d[0]) == 0x1f &&
         static_cast<unsigned char>(d[1]) == 0x8b;
}

// A .trk.gz inflated whole (libdeflate; every gzip member). A TrackVis header declares no data size, so
// the bound is the format's practical one (8 GiB) and deflate's own 1032:1.
std::string gunzipBytes(const std::string& path, const std::string& in) {
  const std::vector<std::uint8_t> out =
      detail::inflateGzip(path, reinterpret_cast<const std::uint8_t*>(in.data()), in.size(), 0, std::size_t(1) << 33,
                  "the gzip data");
  return std::string(out.begin(), out.end());
}

std::string gzipBytes(const std::string&, const std::string& in) {
  const std::vector<std::uint8_t> out = detail::gzipCompress(reinterpret_cast<const std::uint8_t*>(in.data()), in.size());
  return std::string(out.begin(), out.end());
}

glm::dmat4 trkVoxmmToWorld(const TrkInfo& info) {
  // voxmm -> voxel index in the stored voxel order (TrackVis puts the corner of voxel 0 at 0).
  glm::dmat4 toIndex(1.0);
  for (int a = 0; a < 3; ++a) {
    toIndex[a][a] = 1.0 / info.voxelSize[a];
    toIndex[3][a] = -0.5;
  }
  // Stored order -> the affine's order, nibabel's ornt_transform + inv_ornt_aff: output axis a takes
  // input axis perm[a], flipped within dims[a] when the signs differ.
  int hAxis[3], hSign[3], aAxis[3], aSign[3];
  parseAxisCodes(info.voxelOrder, hAxis, hSign);
  parseAxisCodes(axisCodesOf(info.voxToRasUsed), aAxis, aSign);
  glm::dmat4 reorder(0.0);
  reorder[3][3] = 1;
  for (int a = 0; a < 3; ++a) {
    int b = 0;
    while (b < 2 && aAxis[b] != hAxis[a])
      ++b;
    const double flip = hSign[a] == aSign[b] ? 1.0 : -1.0;
    reorder[b][a] = flip;
    if (flip < 0) reorder[3][a] = info.dims[a] - 1;
  }
  return info.voxToRasUsed * reorder * toIndex;
}

} // namespace

glm::dmat4 trkVoxmmToWorldOf(const TrkInfo& info) {
  return trkVoxmmToWorld(info);
}

namespace {

// The 1000-byte header into `info` (checked); returns whether its numbers are byte-swapped.
bool parseTrkHeader(const std::string& path, const std::string& data, TrkInfo& info) {
  if (data.size() < kTrkHeaderSize)
    throw InputError(path + ": truncated TrackVis header (" + std::to_string(data.size()) +
                     " of 1000 bytes)");
  const char* h = data.data();
  if (std::memcmp(h, "TRACK", 5) != 0)
    throw InputError(path + ": not a TrackVis .trk file (no 'TRACK' magic)");
  // hdr_size (offset 996) tells the byte order.
  bool swap = false;
  const int hdrLe = loadScalar<std::int32_t>(h + 996, !kHostLittle);
  const int hdrBe = loadScalar<std::int32_t>(h + 996, kHostLittle);
  if (hdrLe == 1000)
    swap = !kHostLittle;
  else if (hdrBe == 1000)
    swap = kHostLittle, info.bigEndian = true;
  else
    throw InputError(path + ": bad TrackVis header size " + std::to_string(hdrLe) + " (expected 1000)");
  for (int a = 0; a < 3; ++a) {
    info.dims[a] = loadScalar<std::int16_t>(h + 6 + 2 * a, swap);
    info.voxelSize[a] = loadScalar<float>(h + 12 + 4 * a, swap);
    info.origin[a] = loadScalar<float>(h + 24 + 4 * a, swap);
  }
  info.nScalars = loadScalar<std::int16_t>(h + 36, swap);
  info.nProperties = loadScalar<std::int16_t>(h + 238, swap);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      info.voxToRas[c][r] = loadScalar<float>(h + 440 + 4 * (4 * r + c), swap);
  info.voxelOrder.assign(h + 948, strnlen(h + 948, 4));
  info.declaredCount = loadScalar<std::int32_t>(h + 988, swap);
  info.version = loadScalar<std::int32_t>(h + 992, swap);
  if (info.version != 1 && info.version != 2)
    throw InputError(path + ": unsupported TrackVis version " + std::to_string(info.version));
  if (info.nScalars < 0 || info.nScalars > 100 || info.nProperties < 0 || info.nProperties > 100)
    throw InputError(path + ": bad TrackVis n_scalars/n_properties (" + std::to_string(info.nScalars) + ", " +
                     std::to_string(info.nProperties) + ")");
  for (int a = 0; a < 3; ++a)
    if (!(info.voxelSize[a] > 0 && info.voxelSize[a] < 1e4) || info.dims[a] < 0)
      throw InputError(path + ": bad TrackVis voxel size or dimensions");
  if (info.declaredCount < 0) throw InputError(path + ": negative TrackVis track count");
  return swap;
}

// The voxmm -> world mapping of the points (and info's geometry fields), by nibabel's rules: no
// vox_to_ras (element [3][3] zero) means identity; no voxel_order means LPS.
glm::dmat4 trkGeometry(const std::string& path, TrkInfo& info) {
  info.voxToRasUsed = info.voxToRas;
  if (info.voxToRas[3][3] == 0) {
    info.voxToRasUsed = glm::dmat4(1.0);
    info.voxToRasRecorded = false;
    logWarning(path + ": TrackVis header has no vox_to_ras; assuming the identity (as nibabel does)");
  }
  if (info.voxelOrder.empty()) {
    info.voxelOrder = "LPS";
    logWarning(path + ": TrackVis header has no voxel_order; assuming LPS (TrackVis' default)");
  }
  int ax[3], sg[3];
  if (!parseAxisCodes(info.voxelOrder, ax, sg))
    throw InputError(path + ": bad TrackVis voxel_order '" + info.voxelOrder + "'");
  if (!(std::abs(glm::determinant(glm::dmat3(info.voxToRasUsed))) > 1e-12))
    throw InputError(path + ": singular TrackVis vox_to_ras");
  info.affineOrder = axisCodesOf(info.voxToRasUsed);
  const glm::dmat4 toWorld = trkVoxmmToWorld(info);
  info.indexToWorld = toWorld;
  for (int a = 0; a < 3; ++a)
    info.indexToWorld[3] += toWorld[a] * (0.5 * info.voxelSize[a]);
  for (int a = 0; a < 3; ++a)
    info.indexToWorld[a] *= info.voxelSize[a];
  return toWorld;
}

// The track records (count, points with their scalars, properties) into `out`, `scalars` and `props`.
void readTrkRecords(const std::string& path, const std::string& data, const TrkInfo& info, bool swap,
                    const glm::dmat4& toWorld, Polylines& out, std::vector<float>& scalars,
                    std::vector<float>& props) {
  const std::size_t nS = static_cast<std::size_t>(info.nScalars),
                    nP = static_cast<std::size_t>(info.nProperties);
  const std::size_t perPoint = 4u * (3u + nS), perTrackExtra = 4u * nP;
  const std::size_t body = data.size() - kTrkHeaderSize;
  if (info.declaredCount > 0 && static_cast<std::size_t>(info.declaredCount) > body / (4 + perTrackExtra))
    throw InputError(path + ": TrackVis count " + std::to_string(info.declaredCount) + " is impossible for " +
                     std::to_string(body) + " bytes of data");
  out.points.reserve(body / perPoint);
  out.offsets.push_back(0);
  if (nS) scalars.reserve(body / perPoint * nS);
  std::size_t pos = kTrkHeaderSize;
  const double m[12] = {toWorld[0][0], toWorld[1][0], toWorld[2][0], toWorld[3][0],
                        toWorld[0][1], toWorld[1][1], toWorld[2][1], toWorld[3][1],
                        toWorld[0][2], toWorld[1][2], toWorld[2][2], toWorld[3][2]};
  while (pos < data.size()) {
    if (info.declaredCount > 0 && static_cast<long long>(out.lineCount()) == info.declaredCount) break;
    if (data.size() - pos < 4)
      throw InputError(path + ": truncated TrackVis data (partial point count after track " +
                       std::to_string(out.lineCount()) + ")");
    const std::int32_t n = loadScalar<std::int32_t>(data.data() + pos, swap);
    pos += 4;
    if (n < 0 || static_cast<std::size_t>(n) > (data.size() - pos) / perPoint ||
        static_cast<std::size_t>(n) * perPoint + perTrackExtra > data.size() - pos)
      throw InputError(path + ": truncated TrackVis data (track " + std::to_string(out.lineCount()) +
                       " claims " + std::to_string(n) + " points, " + std::to_string(data.size() - pos) +
                       " bytes left)");
    if (out.points.size() + static_cast<std::size_t>(n) >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    for (std::int32_t i = 0; i < n; ++i) {
      const char* p = data.data() + pos + static_cast<std::size_t>(i) * perPoint;
      const double x = loadScalar<float>(p, swap), y = loadScalar<float>(p + 4, swap),
                   z = loadScalar<float>(p + 8, swap);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        throw InputError(path + ": non-finite coordinate in track " + std::to_string(out.lineCount()));
      out.points.emplace_back(static_cast<float>(m[0] * x + m[1] * y + m[2] * z + m[3]),
                              static_cast<float>(m[4] * x + m[5] * y + m[6] * z + m[7]),
                              static_cast<float>(m[8] * x + m[9] * y + m[10] * z + m[11]));
      for (std::size_t k = 0; k < nS; ++k)
        scalars.push_back(loadScalar<float>(p + 12 + 4 * k, swap));
    }
    pos += static_cast<std::size_t>(n) * perPoint;
    for (std::size_t k = 0; k < nP; ++k)
      props.push_back(loadScalar<float>(data.data() + pos + 4 * k, swap));
    pos += perTrackExtra;
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  if (info.declaredCount > 0 && static_cast<long long>(out.lineCount()) < info.declaredCount)
    throw InputError(path + ": truncated TrackVis data (" + std::to_string(out.lineCount()) + " of " +
                     std::to_string(info.declaredCount) + " tracks)");
}

// `items` rows of `width` values, cut into the named slices.
void splitTrkValues(const std::vector<float>& all, std::size_t width, std::size_t items,
                    const std::vector<TrkSlice>& slices, std::vector<TractValues>& to) {
  for (const auto& sl : slices) {
    TractValues v{sl.name, sl.count, {}};
    v.values.resize(items * static_cast<std::size_t>(sl.count));
    for (std::size_t i = 0; i < items; ++i)
      for (int c = 0; c < sl.count; ++c)
        v.values[i * static_cast<std::size_t>(sl.count) + static_cast<std::size_t>(c)] =
            all[i * width + static_cast<std::size_t>(sl.first + c)];
    to.push_back(std::move(v));
  }
}

} // namespace

Polylines readTrk(const std::string& path, TrkInfo* infoOut) {
  std::string data = readAll(path, "tract file");
  TrkInfo info;
  if (isGzip(data)) {
    data = gunzipBytes(path, data);
    info.gzipped = true;
  }
  const bool swap = parseTrkHeader(path, data, info);
  const glm::dmat4 toWorld = trkGeometry(path, info);
  Polylines out;
  std::vector<float> scalars, props;
  readTrkRecords(path, data, info, swap, toWorld, out, scalars, props);
  // Scalars become per-point data and properties per-streamline data, named as nibabel names them.
  const char* h = data.data();
  const auto nS = static_cast<std::size_t>(info.nScalars), nP = static_cast<std::size_t>(info.nProperties);
  if (nS)
    splitTrkValues(scalars, nS, out.points.size(), trkSlices(h + 38, info.nScalars, "scalars"), out.perPoint);
  if (nP)
    splitTrkValues(props, nP, out.lineCount(), trkSlices(h + 240, info.nProperties, "properties"),
                   out.perLine);
  if (infoOut) *infoOut = info;
  return out;
}

namespace {

// Per-point data become scalars and per-streamline data properties, at most 10 names of at most 19
// characters each, written into the header `h` at `at`; a count above 1 is encoded after the name's NUL (as
// nibabel does). Returns the number of values per item.
int encodeTrkNames(const std::string& path, char* h, const std::vector<TractValues>& data, int at,
                   const char* what, std::vector<const TractValues*>& kept) {
  int total = 0;
  std::string dropped;
  for (const auto& d : data) {
    if (kept.size() == 10 || d.name.size() > 18 || d.name.empty() || d.components > 9) {
      dropped += (dropped.empty() ? "'" : ", '") + d.name + "'";
      continue;
    }
    char* f = h + at + 20 * static_cast<int>(kept.size());
    std::memcpy(f, d.name.data(), d.name.size());
    if (d.components > 1) f[d.name.size() + 1] = static_cast<char>('0' + d.components);
    kept.push_back(&d);
    total += d.components;
  }
  if (!dropped.empty())
    logWarning(path + ": a TrackVis file holds at most 10 " + what +
               " (names up to 18 characters, up to 9 values each); dropped " + dropped);
  return total;
}

} // namespace

void writeTrk(const std::string& path, const Polylines& lines, const Grid& reference) {
  checkFinite(lines, path);
  for (int a = 0; a < 3; ++a)
    if (reference.dims[a] <= 0 || reference.dims[a] > 32767 || !(reference.spacing[a] > 0))
      throw InputError("cannot write " + path + ": the reference grid does not fit a TrackVis header");
  if (lines.lineCount() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError("cannot write " + path + ": too many streamlines for TrackVis");
  std::string bytes(kTrkHeaderSize, '\0');
  char* h = bytes.data();
  std::memcpy(h, "TRACK", 5);
  for (int a = 0; a < 3; ++a) {
    putLe<std::int16_t>(h + 6 + 2 * a, static_cast<std::int16_t>(reference.dims[a]));
    putLe<float>(h + 12 + 4 * a, static_cast<float>(reference.spacing[a]));
  }
  std::vector<const TractValues*> sc, pr;
  const int nS = encodeTrkNames(path, h, lines.perPoint, 38, "per-point scalars", sc);
  const int nP = encodeTrkNames(path, h, lines.perLine, 240, "per-streamline properties", pr);
  putLe<std::int16_t>(h + 36, static_cast<std::int16_t>(nS));
  putLe<std::int16_t>(h + 238, static_cast<std::int16_t>(nP));
  if (!lines.groups.empty()) warnDropped(path, "a TrackVis file", {}, {}, lines.groups);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      putLe<float>(h + 440 + 4 * (4 * r + c), static_cast<float>(reference.voxelToWorld[c][r]));
  const std::string order = reference.orientationCode();
  std::memcpy(h + 948, order.data(), std::min<std::size_t>(3, order.size()));
  putLe<std::int32_t>(h + 988, static_cast<std::int32_t>(lines.lineCount()));
  putLe<std::int32_t>(h + 992, 2);
  putLe<std::int32_t>(h + 996, 1000);

  // world -> index -> voxmm = (index + 0.5) * vs; voxel_order is the affine's own, so readers flip nothing.
  // The affine is taken as stored (float) so that a reader using the header's numbers inverts exactly what
  // was applied.
  glm::dmat4 stored(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      stored[c][r] = static_cast<double>(static_cast<float>(reference.voxelToWorld[c][r]));
  const glm::dmat4 worldToIndex = glm::inverse(stored);
  bytes.reserve(kTrkHeaderSize + (4 + 4 * static_cast<std::size_t>(nP)) * lines.lineCount() +
                (12 + 4 * static_cast<std::size_t>(nS)) * lines.points.size());
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    storeLe<std::int32_t>(bytes, static_cast<std::int32_t>(lines.offsets[l + 1] - lines.offsets[l]));
    for (std::uint32_t i = lines.offsets[l]; i < lines.offsets[l + 1]; ++i) {
      glm::dvec4 idx = worldToIndex * glm::dvec4(glm::dvec3(lines.points[i]), 1.0);
      for (int a = 0; a < 3; ++a)
        storeLe<float>(bytes, static_cast<float>((idx[a] + 0.5) * static_cast<float>(reference.spacing[a])));
      for (const TractValues* d : sc)
        for (int c = 0; c < d->components; ++c)
          storeLe<float>(bytes,
                         d->values[static_cast<std::size_t>(i) * static_cast<std::size_t>(d->components) +
                                   static_cast<std::size_t>(c)]);
    }
    for (const TractValues* d : pr)
      for (int c = 0; c < d->components; ++c)
        storeLe<float>(bytes,
                       d->values[l * static_cast<std::size_t>(d->components) + static_cast<std::size_t>(c)]);
  }
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.size() > 3 && lower.compare(lower.size() - 3, 3, ".gz") == 0) bytes = gzipBytes(path, bytes);
  writeFileAtomically(path, bytes);
}

} // namespace dtf::io
