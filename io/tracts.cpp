#include "io/tracts.h"

#include "io/atomic_file.h"
#include "io/model/error.h"
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
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": cannot read " + what + ": no such file");
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

std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

} // namespace

// ---------------------------------------------------------------------------------------------------- .tck

Polylines readTck(const std::string& path, TckInfo* infoOut) {
  const std::string data = readAll(path, "tract file");
  TckInfo info;
  // Header: lines up to "END". Its size is bounded by the data offset; refuse runaway headers.
  std::size_t pos = 0;
  bool first = true, ended = false;
  while (pos < data.size() && pos < (1u << 24)) {
    std::size_t nl = data.find('\n', pos);
    if (nl == std::string::npos) break;
    std::string line = trim(data.substr(pos, nl - pos));
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
  const std::size_t headerEnd = pos;

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
  int width = 0;
  bool big = false;
  if (info.datatype == "Float32LE")
    width = 4;
  else if (info.datatype == "Float32BE")
    width = 4, big = true;
  else if (info.datatype == "Float64LE")
    width = 8;
  else if (info.datatype == "Float64BE")
    width = 8, big = true;
  else if (info.datatype.empty())
    throw InputError(path + ": .tck header has no datatype");
  else
    throw InputError(path + ": unsupported .tck datatype '" + info.datatype + "'");

  if (file.empty()) throw InputError(path + ": .tck header has no 'file:' entry");
  {
    std::istringstream ss(file);
    std::string dot;
    long long off = -1;
    ss >> dot >> off;
    if (dot != ".")
      throw InputError(path + ": .tck data in a separate file ('" + file + "') is not supported");
    if (ss.fail() || off < 0) throw InputError(path + ": bad .tck data offset in 'file: " + file + "'");
    if (static_cast<unsigned long long>(off) < headerEnd ||
        static_cast<unsigned long long>(off) > data.size())
      throw InputError(path + ": .tck data offset " + std::to_string(off) + " lies " +
                       (static_cast<unsigned long long>(off) < headerEnd ? "inside the header"
                                                                         : "beyond the end of the file") +
                       " (file size " + std::to_string(data.size()) + " bytes)");
    info.dataOffset = static_cast<std::size_t>(off);
  }

  const std::size_t triplet = 3u * static_cast<std::size_t>(width);
  const std::size_t available = data.size() - info.dataOffset;
  const std::size_t triplets = available / triplet;
  // Each streamline needs at least its NaN separator triplet.
  if (info.declaredCount > static_cast<long long>(triplets))
    throw InputError(path + ": .tck count " + std::to_string(info.declaredCount) + " is impossible for " +
                     std::to_string(available) + " bytes of data");
  const bool swap = big == kHostLittle;

  Polylines out;
  out.points.reserve(triplets);
  out.offsets.push_back(0);
  bool terminated = false;
  const char* base = data.data() + info.dataOffset;
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
    if (infs == 3) {
      terminated = true;
      break;
    }
    if (nans || infs)
      throw InputError(path + ": non-finite coordinate in triplet " + std::to_string(t) +
                       " of the .tck data");
    if (std::abs(v[0]) > 1e7 || std::abs(v[1]) > 1e7 || std::abs(v[2]) > 1e7)
      throw InputError(path + ": absurd coordinate in triplet " + std::to_string(t) + " of the .tck data");
    if (out.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    out.points.emplace_back(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  }
  if (!terminated) {
    const bool partial = available % triplet != 0;
    throw InputError(path + ": truncated .tck data (" +
                     (partial ? std::string("ends inside a triplet") : std::string("no end-of-file marker")) +
                     " after " + std::to_string(out.offsets.size() - 1) + " streamlines)");
  }
  if (out.offsets.back() != out.points.size())
    throw InputError(path + ": truncated .tck data (the last streamline has no NaN separator)");
  if (info.declaredCount >= 0 && static_cast<std::size_t>(info.declaredCount) != out.lineCount())
    logWarning(path + ": header count " + std::to_string(info.declaredCount) + " but " +
               std::to_string(out.lineCount()) + " streamlines in the file");
  if (infoOut) *infoOut = std::move(info);
  return out;
}

void writeTck(const std::string& path, const Polylines& lines) {
  checkFinite(lines, path);
  std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: " + std::to_string(lines.lineCount()) +
                     "\ntotal_count: " + std::to_string(lines.lineCount()) + "\nfile: . ";
  // The offset is written with a fixed width so its own length is known.
  const std::size_t offset = head.size() + 10 + 5; // digits + "\nEND\n"
  char digits[16];
  std::snprintf(digits, sizeof digits, "%-10zu", offset);
  std::string bytes = head + std::string(digits, 10) + "\nEND\n";
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

// Affine from TrackVis voxel_order when vox_to_ras is absent: axis letters give direction and sign.
bool affineFromVoxelOrder(const std::string& order, const glm::dvec3& vs, glm::dmat4& out) {
  if (order.size() < 3) return false;
  out = glm::dmat4(0.0);
  out[3][3] = 1;
  bool used[3] = {false, false, false};
  for (int axis = 0; axis < 3; ++axis) {
    char c = static_cast<char>(std::toupper(static_cast<unsigned char>(order[axis])));
    int world = -1;
    double sign = 1;
    switch (c) {
    case 'R':
      world = 0;
      break;
    case 'L':
      world = 0, sign = -1;
      break;
    case 'A':
      world = 1;
      break;
    case 'P':
      world = 1, sign = -1;
      break;
    case 'S':
      world = 2;
      break;
    case 'I':
      world = 2, sign = -1;
      break;
    default:
      return false;
    }
    if (used[world]) return false;
    used[world] = true;
    out[axis][world] = sign * vs[axis]; // column `axis`, row `world`
  }
  return true;
}

} // namespace

Polylines readTrk(const std::string& path, TrkInfo* infoOut) {
  const std::string data = readAll(path, "tract file");
  if (data.size() < kTrkHeaderSize)
    throw InputError(path + ": truncated TrackVis header (" + std::to_string(data.size()) +
                     " of 1000 bytes)");
  const char* h = data.data();
  if (std::memcmp(h, "TRACK", 5) != 0)
    throw InputError(path + ": not a TrackVis .trk file (no 'TRACK' magic)");
  TrkInfo info;
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
  if (info.nScalars < 0 || info.nScalars > 10 || info.nProperties < 0 || info.nProperties > 10)
    throw InputError(path + ": bad TrackVis n_scalars/n_properties (" + std::to_string(info.nScalars) + ", " +
                     std::to_string(info.nProperties) + ")");
  for (int a = 0; a < 3; ++a)
    if (!(info.voxelSize[a] > 0 && info.voxelSize[a] < 1e4) || info.dims[a] < 0)
      throw InputError(path + ": bad TrackVis voxel size or dimensions");
  if (info.declaredCount < 0) throw InputError(path + ": negative TrackVis track count");

  bool haveAffine = false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (info.voxToRas[c][r] != 0) haveAffine = true;
  if (haveAffine && info.voxToRas[3][3] != 0) {
    info.indexToWorld = info.voxToRas;
  } else if (affineFromVoxelOrder(info.voxelOrder, info.voxelSize, info.indexToWorld)) {
    logWarning(path + ": TrackVis header has no vox_to_ras; using voxel_order " + info.voxelOrder +
               " with voxel (0,0,0) at the origin");
  } else if (!info.voxelOrder.empty()) {
    throw InputError(path + ": bad TrackVis voxel_order '" + info.voxelOrder +
                     "' and no vox_to_ras (orientation unknown)");
  } else {
    info.indexToWorld = glm::dmat4(1.0);
    for (int a = 0; a < 3; ++a)
      info.indexToWorld[a][a] = info.voxelSize[a];
    logWarning(path +
               ": TrackVis header has neither vox_to_ras nor a voxel_order; assuming RAS at the origin");
  }
  if (!(std::abs(glm::determinant(glm::dmat3(info.indexToWorld))) > 1e-12))
    throw InputError(path + ": singular TrackVis vox_to_ras");

  // Point record: xyz + scalars; track record: count + points + properties.
  const std::size_t perPoint = 4u * (3u + static_cast<std::size_t>(info.nScalars));
  const std::size_t perTrackExtra = 4u * static_cast<std::size_t>(info.nProperties);
  const std::size_t body = data.size() - kTrkHeaderSize;
  if (info.declaredCount > 0 && static_cast<std::size_t>(info.declaredCount) > body / (4 + perTrackExtra))
    throw InputError(path + ": TrackVis count " + std::to_string(info.declaredCount) + " is impossible for " +
                     std::to_string(body) + " bytes of data");

  // voxmm -> index: p / vs - 0.5; then index -> world.
  glm::dmat4 m = info.indexToWorld;
  glm::dmat4 voxmmToIndex(1.0);
  for (int a = 0; a < 3; ++a) {
    voxmmToIndex[a][a] = 1.0 / info.voxelSize[a];
    voxmmToIndex[3][a] = -0.5;
  }
  const glm::dmat4 toWorld = m * voxmmToIndex;

  Polylines out;
  out.points.reserve(body / perPoint);
  out.offsets.push_back(0);
  std::size_t pos = kTrkHeaderSize;
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
    for (std::int32_t i = 0; i < n; ++i) {
      const char* p = data.data() + pos + static_cast<std::size_t>(i) * perPoint;
      glm::dvec4 v(loadScalar<float>(p, swap), loadScalar<float>(p + 4, swap), loadScalar<float>(p + 8, swap),
                   1.0);
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw InputError(path + ": non-finite coordinate in track " + std::to_string(out.lineCount()));
      glm::dvec4 w = toWorld * v;
      out.points.emplace_back(static_cast<float>(w.x), static_cast<float>(w.y), static_cast<float>(w.z));
    }
    pos += static_cast<std::size_t>(n) * perPoint + perTrackExtra;
    if (out.points.size() >= std::numeric_limits<std::uint32_t>::max())
      throw InputError(path + ": too many points for one tract set");
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  if (info.declaredCount > 0 && static_cast<long long>(out.lineCount()) < info.declaredCount)
    throw InputError(path + ": truncated TrackVis data (" + std::to_string(out.lineCount()) + " of " +
                     std::to_string(info.declaredCount) + " tracks)");
  if (infoOut) *infoOut = info;
  return out;
}

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
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      putLe<float>(h + 440 + 4 * (4 * r + c), static_cast<float>(reference.voxelToWorld[c][r]));
  const std::string order = reference.orientationCode();
  std::memcpy(h + 948, order.data(), std::min<std::size_t>(3, order.size()));
  putLe<std::int32_t>(h + 988, static_cast<std::int32_t>(lines.lineCount()));
  putLe<std::int32_t>(h + 992, 2);
  putLe<std::int32_t>(h + 996, 1000);

  // world -> index -> voxmm = (index + 0.5) * vs. The affine is taken as stored (float) so that a reader
  // using the header's numbers inverts exactly what was applied.
  glm::dmat4 stored(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      stored[c][r] = static_cast<double>(static_cast<float>(reference.voxelToWorld[c][r]));
  const glm::dmat4 worldToIndex = glm::inverse(stored);
  bytes.reserve(kTrkHeaderSize + 4 * lines.lineCount() + 12 * lines.points.size());
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    storeLe<std::int32_t>(bytes, static_cast<std::int32_t>(lines.offsets[l + 1] - lines.offsets[l]));
    for (std::uint32_t i = lines.offsets[l]; i < lines.offsets[l + 1]; ++i) {
      glm::dvec4 idx = worldToIndex * glm::dvec4(glm::dvec3(lines.points[i]), 1.0);
      for (int a = 0; a < 3; ++a)
        storeLe<float>(bytes, static_cast<float>((idx[a] + 0.5) * static_cast<float>(reference.spacing[a])));
    }
  }
  writeFileAtomically(path, bytes);
}

} // namespace dtf::io
