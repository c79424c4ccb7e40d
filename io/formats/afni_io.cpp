// SPDX-License-Identifier: GPL-3.0-or-later
// AFNI datasets (+orig/+tlrc/+acpc .HEAD with .BRIK or .BRIK.gz): scalar and vector bricks. The HEAD file
// is a list of attributes ("type = ...", "name = ...", "count = N", then the values). Geometry:
// IJK_TO_DICOM_REAL (else IJK_TO_DICOM, else ORIGIN/DELTA with ORIENT_SPECIFIC) maps (i, j, k) to AFNI's
// DICOM coordinates, +x left, +y posterior, +z superior (LPS); world RAS = diag(-1, -1, 1) * that.
// Bricks: BRICK_TYPES (0 byte, 1 short, 3 float, 5 double; complex and RGB refused), BRICK_FLOAT_FACS
// (0 = unscaled), BYTEORDER_STRING (LSB_FIRST / MSB_FIRST); each brick is a whole volume, i fastest.
#include "io/formats/format_detail.h"
#include "io/formats/gzip.h"
#include "io/model/error.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::io::detail {

namespace {

struct Attr {
  std::vector<double> numbers;
  std::string text;
};

std::map<std::string, Attr> readHead(const std::string& path) {
  const std::vector<std::uint8_t> b = readFileBytes(path, nullptr, std::size_t(1) << 26);
  const std::string s(b.begin(), b.end());
  std::map<std::string, Attr> out;
  std::size_t p = 0;
  while ((p = s.find("type", p)) != std::string::npos) {
    const std::size_t eol = s.find('\n', p);
    if (eol == std::string::npos) break;
    const std::string typeLine = s.substr(p, eol - p);
    const bool isString = typeLine.find("string-attribute") != std::string::npos;
    const std::size_t nameAt = s.find("name", eol);
    const std::size_t countAt = s.find("count", eol);
    if (nameAt == std::string::npos || countAt == std::string::npos) break;
    const std::size_t nameEq = s.find('=', nameAt), nameEnd = s.find('\n', nameAt);
    const std::size_t countEq = s.find('=', countAt), countEnd = s.find('\n', countAt);
    if (nameEq == std::string::npos || nameEnd == std::string::npos || countEq == std::string::npos ||
        countEnd == std::string::npos || nameEq > nameEnd || countEq > countEnd)
      fail(path, "malformed attribute near byte " + std::to_string(p));
    std::string name = s.substr(nameEq + 1, nameEnd - nameEq - 1);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t\r") + 1);
    const long long count = std::atoll(s.c_str() + countEq + 1);
    if (count < 0 || count > (1 << 24)) fail(path, "attribute " + name + " has an absurd count");
    Attr a;
    std::size_t q = countEnd + 1;
    if (isString) {
      const std::size_t quote = s.find('\'', q);
      if (quote == std::string::npos) fail(path, "string attribute " + name + " has no opening quote");
      a.text =
          s.substr(quote + 1, std::min<std::size_t>(static_cast<std::size_t>(count), s.size() - quote - 1));
      q = quote + 1 + a.text.size();
    } else {
      std::istringstream in(
          s.substr(q, std::min<std::size_t>(s.size() - q, static_cast<std::size_t>(count) * 40 + 64)));
      for (long long n = 0; n < count; ++n) {
        double v;
        if (!(in >> v))
          fail(path, "attribute " + name + " holds fewer than " + std::to_string(count) + " numbers");
        a.numbers.push_back(v);
      }
      const std::streamoff used = in.tellg();
      q += used > 0 ? static_cast<std::size_t>(used) : 0;
    }
    out[name] = std::move(a);
    p = std::max(q, countEnd + 1);
  }
  return out;
}

const Attr& need(const std::string& path, const std::map<std::string, Attr>& a, const char* name) {
  const auto it = a.find(name);
  if (it == a.end()) fail(path, std::string("has no ") + name + " attribute");
  return it->second;
}

} // namespace

std::string afniBrikFile(const std::string& head) {
  std::string base = head.substr(0, head.size() - 5); // strip ".HEAD"
  std::error_code ec;
  for (const char* ext : {".BRIK", ".BRIK.gz"})
    if (fs::is_regular_file(base + ext, ec)) return base + ext;
  return {};
}

namespace {

// The bricks as components (BRICK_FLOAT_FACS applied, 0 meaning 1), in the stored byte order.
ScalarVolume afniBricks(const std::map<std::string, Attr>& a, const Grid& grid,
                        const std::vector<SampleType>& types, const std::vector<std::uint8_t>& data) {
  const int bricks = static_cast<int>(types.size());
  const auto nv = static_cast<long long>(grid.voxelCount());
  bool big = false;
  if (const auto o = a.find("BYTEORDER_STRING"); o != a.end())
    big = o->second.text.rfind("MSB_FIRST", 0) == 0;
  std::vector<double> facs(static_cast<std::size_t>(bricks), 0.0);
  if (const auto f = a.find("BRICK_FLOAT_FACS"); f != a.end())
    for (std::size_t k = 0; k < facs.size() && k < f->second.numbers.size(); ++k)
      facs[k] = f->second.numbers[k];
  ScalarVolume v(grid, bricks);
  std::size_t at = 0;
  for (int k = 0; k < bricks; ++k) {
    const SampleTypeInfo& type = sampleTypeInfo(types[static_cast<std::size_t>(k)]);
    const auto s = static_cast<std::size_t>(type.bytes);
    const double fac = facs[static_cast<std::size_t>(k)] != 0 ? facs[static_cast<std::size_t>(k)] : 1.0;
    for (long long i = 0; i < nv; ++i, at += s) {
      const double x = type.fetch(data.data() + at, big);
      v.data[static_cast<std::size_t>(i) * static_cast<std::size_t>(bricks) + static_cast<std::size_t>(k)] =
          static_cast<float>(x * fac);
    }
  }
  return v;
}

// The grid: IJK_TO_DICOM[_REAL] when present, else ORIENT_SPECIFIC, ORIGIN and DELTA, from AFNI's DICOM
// (LPS) to RAS. `source` names the attributes used.
Grid afniGrid(const std::string& path, const std::map<std::string, Attr>& a, const glm::ivec3& gd,
              std::string& source) {
  // Geometry (AFNI DICOM = LPS).
  glm::dmat4 lps(1.0);
  const auto m = a.count("IJK_TO_DICOM_REAL") ? a.find("IJK_TO_DICOM_REAL") : a.find("IJK_TO_DICOM");
  if (m != a.end() && m->second.numbers.size() == 12) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        lps[c][r] = m->second.numbers[static_cast<std::size_t>(r * 4 + c)];
    source = m->first;
  } else {
    const Attr& orient = need(path, a, "ORIENT_SPECIFIC");
    const Attr& origin = need(path, a, "ORIGIN");
    const Attr& delta = need(path, a, "DELTA");
    if (orient.numbers.size() < 3 || origin.numbers.size() < 3 || delta.numbers.size() < 3)
      fail(path, "ORIENT_SPECIFIC, ORIGIN or DELTA too short");
    for (int d = 0; d < 3; ++d) {
      const double raw = orient.numbers[static_cast<std::size_t>(d)];
      if (!(raw >= 0 && raw <= 5)) fail(path, "ORIENT_SPECIFIC code " + std::to_string(raw) + " is not 0..5");
      const int code = static_cast<int>(raw);
      // 0 R-to-L, 1 L-to-R, 2 P-to-A, 3 A-to-P, 4 I-to-S, 5 S-to-I: the DICOM axis each voxel axis runs
      // along; DELTA already carries the sign of the step in DICOM coordinates.
      lps[d][code / 2] = delta.numbers[static_cast<std::size_t>(d)];
      lps[3][code / 2] = origin.numbers[static_cast<std::size_t>(d)];
    }
    source = "ORIENT_SPECIFIC, ORIGIN, DELTA";
  }
  glm::dmat4 toRas(1.0);
  toRas[0][0] = -1;
  toRas[1][1] = -1;
  const glm::dmat4 affine = toRas * lps;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(affine[c][r])) fail(path, "the voxel-to-world mapping (" + source + ") is not finite");
  if (!(std::abs(glm::determinant(glm::dmat3(affine))) >= 1e-12))
    fail(path, "the voxel-to-world mapping is singular");
  return Grid::fromAffine(gd, affine);
}

} // namespace

ScalarVolume readAfni(const std::string& path, VolumeHeader* header, bool withData) {
  if (!endsWith(path, ".HEAD")) fail(path, "an AFNI dataset is opened by its .HEAD file");
  const auto a = readHead(path);
  const Attr& dims = need(path, a, "DATASET_DIMENSIONS");
  const Attr& rank = need(path, a, "DATASET_RANK");
  if (dims.numbers.size() < 3 || rank.numbers.size() < 2)
    fail(path, "DATASET_DIMENSIONS or DATASET_RANK too short");
  glm::ivec3 gd;
  long long nv = 1;
  for (int d = 0; d < 3; ++d) {
    const double n = dims.numbers[static_cast<std::size_t>(d)];
    if (!(n >= 1) || n > 1e6) fail(path, "dimension " + std::to_string(n) + " is not a whole number >= 1");
    gd[d] = static_cast<int>(n);
    nv *= gd[d];
  }
  const double bricksD = rank.numbers[1];
  if (!(bricksD >= 1) || bricksD > 1e5)
    fail(path, "DATASET_RANK gives " + std::to_string(bricksD) + " bricks");
  const int bricks = static_cast<int>(bricksD);
  if (nv > kMaxValues / bricks)
    fail(path, "dimensions are absurd (more than 2^31 values); refusing to allocate");
  std::string source;
  const Grid grid = afniGrid(path, a, gd, source);
  const Attr& typeCodes = need(path, a, "BRICK_TYPES");
  if (static_cast<int>(typeCodes.numbers.size()) < bricks)
    fail(path, "BRICK_TYPES lists fewer types than bricks");
  std::vector<SampleType> types;
  long long bytes = 0;
  for (int k = 0; k < bricks; ++k) {
    const double raw = typeCodes.numbers[static_cast<std::size_t>(k)];
    const int t = raw >= 0 && raw <= 10 ? static_cast<int>(raw) : -1;
    // AFNI brick types 0 byte, 1 short, 3 float, 5 double onto the sample table.
    if (t != 0 && t != 1 && t != 3 && t != 5)
      fail(path, "brick type " + std::to_string(t) + " is not read (byte, short, float and double are)");
    types.push_back(t == 0   ? SampleType::UInt8
                    : t == 1 ? SampleType::Int16
                    : t == 3 ? SampleType::Float32
                             : SampleType::Float64);
    bytes += nv * sampleTypeInfo(types.back()).bytes;
  }
  if (header) {
    *header = VolumeHeader{};
    header->path = path;
    header->niftiVersion = 0;
    header->dims = {gd.x, gd.y, gd.z};
    if (bricks > 1) header->dims.push_back(bricks);
    header->grid = grid;
    header->datatypeName = "AFNI brick type " + std::to_string(static_cast<int>(typeCodes.numbers[0]));
    header->affineSource = source + " (AFNI DICOM/LPS) -> RAS";
    if (const auto l = a.find("BRICK_LABS"); l != a.end()) header->intentName = l->second.text;
  }
  const std::string brik = afniBrikFile(path);
  if (brik.empty()) fail(path, "no .BRIK or .BRIK.gz beside it");
  if (!withData) return {};
  // Nothing is read when the file cannot hold the bricks; a .BRIK.gz is inflated into the size the header
  // declares, and refused when it runs far beyond it.
  checkInflatable(path, "data file " + brik + " ", brik, static_cast<unsigned long long>(bytes));
  const bool gz = endsWith(brik, ".gz");
  const auto declared = static_cast<std::size_t>(bytes);
  const std::vector<std::uint8_t> data =
      gz ? readFileBytes(brik, nullptr, inflateLimit(declared), declared) : readFileBytes(brik);
  if (static_cast<long long>(data.size()) < bytes)
    fail(path, "data file " + brik + " is truncated: " + std::to_string(data.size()) +
                   " bytes, the header needs " + std::to_string(bytes));
  return afniBricks(a, grid, types, data);
}

} // namespace dtf::io::detail
