// SPDX-License-Identifier: GPL-3.0-or-later
// NRRD (teem's format, NRRD0001-0005): attached (.nrrd) and detached (.nhdr + data file) headers; raw,
// gzip and ascii encodings; either endianness. Axes are read in the order the header lists them (axis 0
// fastest); the axes with a space direction (or, without `space directions`, those whose kind is not a
// tensor/list kind) are the voxel axes i, j, k in that order, and at most one other axis becomes the
// components. Geometry: voxel -> space = [space directions | space origin], then LPS (or LAS) -> RAS.
// Tensors (kinds 3D-symmetric-matrix: xx xy xz yy yz zz; 3D-masked-symmetric-matrix: a leading confidence,
// voxels with confidence < 0.5 are masked out as teem's tend does) are stored in the measurement frame:
// D_space = M D M^T, M's columns being the `measurement frame` vectors (the NRRD format definition), then
// D_ras = S D_space S with S = diag(-1, -1, 1) for LPS.
#include "io/formats/format_detail.h"
#include "io/formats/gzip.h"
#include "io/model/error.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::io::detail {

namespace {

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  std::string w;
  while (in >> w)
    out.push_back(w);
  return out;
}

// NRRD's type names onto the sample table.
SampleType parseType(const std::string& path, const std::string& t) {
  static const std::map<std::string, SampleType> kTypes = {{"signed char", SampleType::Int8},
                                                           {"int8", SampleType::Int8},
                                                           {"int8_t", SampleType::Int8},
                                                           {"uchar", SampleType::UInt8},
                                                           {"unsigned char", SampleType::UInt8},
                                                           {"uint8", SampleType::UInt8},
                                                           {"uint8_t", SampleType::UInt8},
                                                           {"short", SampleType::Int16},
                                                           {"short int", SampleType::Int16},
                                                           {"signed short", SampleType::Int16},
                                                           {"signed short int", SampleType::Int16},
                                                           {"int16", SampleType::Int16},
                                                           {"int16_t", SampleType::Int16},
                                                           {"ushort", SampleType::UInt16},
                                                           {"unsigned short", SampleType::UInt16},
                                                           {"unsigned short int", SampleType::UInt16},
                                                           {"uint16", SampleType::UInt16},
                                                           {"uint16_t", SampleType::UInt16},
                                                           {"int", SampleType::Int32},
                                                           {"signed int", SampleType::Int32},
                                                           {"int32", SampleType::Int32},
                                                           {"int32_t", SampleType::Int32},
                                                           {"uint", SampleType::UInt32},
                                                           {"unsigned int", SampleType::UInt32},
                                                           {"uint32", SampleType::UInt32},
                                                           {"uint32_t", SampleType::UInt32},
                                                           {"longlong", SampleType::Int64},
                                                           {"long long", SampleType::Int64},
                                                           {"long long int", SampleType::Int64},
                                                           {"signed long long", SampleType::Int64},
                                                           {"signed long long int", SampleType::Int64},
                                                           {"int64", SampleType::Int64},
                                                           {"int64_t", SampleType::Int64},
                                                           {"ulonglong", SampleType::UInt64},
                                                           {"unsigned long long", SampleType::UInt64},
                                                           {"unsigned long long int", SampleType::UInt64},
                                                           {"uint64", SampleType::UInt64},
                                                           {"uint64_t", SampleType::UInt64},
                                                           {"float", SampleType::Float32},
                                                           {"double", SampleType::Float64}};
  const auto it = kTypes.find(t);
  if (it == kTypes.end())
    fail(path, "unsupported type '" + t + "' (integer types, float and double are read)");
  return it->second;
}

// "(1,0,0)" -> vector; "none" -> nullopt-like flag.
bool parseVector(const std::string& path, const std::string& key, const std::string& text, glm::dvec3& v) {
  if (text == "none") return false;
  if (text.size() < 2 || text.front() != '(' || text.back() != ')')
    fail(path, "'" + key + "' entry '" + text + "' is not a vector like (1,0,0)");
  std::string inner = text.substr(1, text.size() - 2);
  std::replace(inner.begin(), inner.end(), ',', ' ');
  std::istringstream in(inner);
  double a[3];
  for (double& x : a)
    if (!(in >> x) || !std::isfinite(x))
      fail(path, "'" + key + "' entry '" + text + "' is not 3 finite numbers");
  std::string rest;
  if (in >> rest) fail(path, "'" + key + "' entry '" + text + "' has more than 3 numbers (3D spaces only)");
  v = glm::dvec3(a[0], a[1], a[2]);
  return true;
}

// Vector entries separated by spaces, each in parentheses or "none".
std::vector<std::string> vectorEntries(const std::string& s) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t'))
      ++i;
    if (i >= s.size()) break;
    std::size_t j = i;
    if (s[i] == '(') {
      j = s.find(')', i);
      j = j == std::string::npos ? s.size() : j + 1;
    } else {
      while (j < s.size() && s[j] != ' ' && s[j] != '\t')
        ++j;
    }
    out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// True when the columns of `m` do not span 3D space: |det| tiny beside the product of the column lengths
// (scale-free, so 0.1 mm voxels are not singular), or not finite.
bool singular(const glm::dmat3& m) {
  const double scale = glm::length(m[0]) * glm::length(m[1]) * glm::length(m[2]);
  const double det = glm::determinant(m);
  return !std::isfinite(det) || !std::isfinite(scale) || !(scale > 0) || std::abs(det) <= 1e-6 * scale;
}

// The header of a NRRD file as written ("field: value" lines), with its axes sorted out.
struct NrrdDescription {
  std::map<std::string, std::string> fields;
  std::size_t headerEnd = 0; // byte after the header (the blank line) in the file
  bool blank = false;        // the header ended with a blank line (attached data follow)
  const SampleTypeInfo* type = nullptr;
  int ndim = 0;
  std::vector<long long> sizes; // as stored
  long long total = 1;
  std::vector<std::string> kinds;
  std::vector<glm::dvec3> dirs; // per axis, in the header's space
  std::vector<int> spatialAxes;
  int compAxis = -1;
  bool spaceDirs = false; // directions from 'space directions' (else from spacings)

  // The value of field `a` (or its alternative spelling `b`), or null.
  const std::string* field(const std::string& a, const std::string& b = "") const {
    auto it = fields.find(a);
    if (it == fields.end() && !b.empty()) it = fields.find(b);
    return it == fields.end() ? nullptr : &it->second;
  }
};

void parseNrrdFields(const std::string& path, const std::vector<std::uint8_t>& bytes, NrrdDescription& d) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), "NRRD000", 7) != 0)
    fail(path, "not a NRRD file (no 'NRRD000x' magic at the start)");
  std::size_t pos = 0;
  int lineNo = 0;
  while (pos < bytes.size()) {
    std::size_t eol = pos;
    while (eol < bytes.size() && bytes[eol] != '\n')
      ++eol;
    std::string line(bytes.begin() + static_cast<std::ptrdiff_t>(pos),
                     bytes.begin() + static_cast<std::ptrdiff_t>(eol));
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = std::min(eol + 1, bytes.size());
    if (++lineNo == 1) continue;
    if (line.empty()) {
      d.blank = true;
      break;
    }
    if (line[0] == '#') continue;
    if (line.find(":=") != std::string::npos) continue; // key/value pairs
    const auto colon = line.find(": ");
    if (colon == std::string::npos)
      fail(path, "header line " + std::to_string(lineNo) + " is not 'field: value'");
    d.fields[trim(line.substr(0, colon))] = trim(line.substr(colon + 2));
    if (lineNo > 10000) fail(path, "header longer than 10000 lines");
  }
  d.headerEnd = pos;
}

// type, dimension, sizes and kinds.
void nrrdSizes(const std::string& path, NrrdDescription& d) {
  for (const char* req : {"type", "dimension", "sizes", "encoding"})
    if (!d.field(req)) fail(path, std::string("the header has no '") + req + "' field");
  d.type = &sampleTypeInfo(parseType(path, *d.field("type")));
  const std::string dimText = *d.field("dimension");
  if (dimText.empty() || dimText.find_first_not_of("0123456789") != std::string::npos || dimText.size() > 2)
    fail(path, "dimension '" + dimText + "' is not a small whole number");
  d.ndim = std::stoi(dimText);
  if (d.ndim < 3 || d.ndim > 4)
    fail(path, "dimension " + dimText + " (3D volumes, or 4D with one component axis, are read)");
  for (const std::string& w : words(*d.field("sizes"))) {
    if (w.find_first_not_of("0123456789") != std::string::npos || w.size() > 12)
      fail(path, "sizes entry '" + w + "' is not a whole number");
    d.sizes.push_back(std::stoll(w));
    if (d.sizes.back() < 1) fail(path, "sizes entry " + w + " must be >= 1");
  }
  if (static_cast<int>(d.sizes.size()) != d.ndim)
    fail(path, "'sizes' has " + std::to_string(d.sizes.size()) + " entries for dimension " + dimText);
  for (long long n : d.sizes) {
    if (d.total > kMaxValues / n)
      fail(path, "sizes are absurd (more than 2^31 values); refusing to allocate");
    d.total *= n;
  }
  d.kinds.assign(static_cast<std::size_t>(d.ndim), "");
  if (const std::string* k = d.field("kinds")) {
    d.kinds = words(*k);
    // Multi-word kinds do not exist; "3D-symmetric-matrix" is one word.
    if (static_cast<int>(d.kinds.size()) != d.ndim)
      fail(path, "'kinds' has " + std::to_string(d.kinds.size()) + " entries for dimension " + dimText);
  }
}

// Axis directions from 'spacings' and the kinds (no 'space directions'): spatial axes along x, y, z.
void nrrdDirectionsFromSpacings(const NrrdDescription& d, std::vector<glm::dvec3>& dirs,
                                std::vector<bool>& spatial, std::vector<std::string>& warnings) {
  std::vector<double> spacings(static_cast<std::size_t>(d.ndim), 1.0);
  std::vector<std::string> given(static_cast<std::size_t>(d.ndim));
  if (const std::string* sp = d.field("spacings")) {
    const auto w = words(*sp);
    for (std::size_t a = 0; a < w.size() && a < spacings.size(); ++a) {
      char* end = nullptr;
      const double v = std::strtod(w[a].c_str(), &end);
      spacings[a] = std::isfinite(v) && v > 0 ? v : 1.0;
      if (!(std::isfinite(v) && v > 0)) given[a] = w[a];
    }
  }
  int axis = 0;
  for (std::size_t a = 0; a < static_cast<std::size_t>(d.ndim); ++a) {
    const std::string& k = d.kinds[a];
    if (k.empty() || k == "domain" || k == "space") {
      spatial[a] = true;
      glm::dvec3 v(0.0);
      if (axis < 3) v[axis] = spacings[a];
      if (!given[a].empty())
        warnings.push_back("spacing '" + given[a] + "' of axis " + std::to_string(a) +
                           " is not a positive number: 1 mm assumed");
      dirs[a] = v;
      ++axis;
    }
  }
}

// Which axes are spatial (and their directions), which one holds components.
void nrrdAxes(const std::string& path, NrrdDescription& d, NrrdVolume& out) {
  const auto n = static_cast<std::size_t>(d.ndim);
  d.dirs.assign(n, glm::dvec3(0.0));
  std::vector<bool> spatial(n, false);
  const std::string* spaceDirs = d.field("space directions");
  d.spaceDirs = spaceDirs != nullptr;
  if (spaceDirs) {
    const std::vector<std::string> e = vectorEntries(*spaceDirs);
    if (e.size() != n)
      fail(path, "'space directions' has " + std::to_string(e.size()) + " entries for dimension " +
                     std::to_string(d.ndim));
    for (std::size_t a = 0; a < n; ++a)
      spatial[a] = parseVector(path, "space directions", e[a], d.dirs[a]);
  } else {
    nrrdDirectionsFromSpacings(d, d.dirs, spatial, out.header.warnings);
    out.header.warnings.emplace_back("no 'space directions': orientation unknown, assuming RAS voxel axes");
  }
  for (int a = 0; a < d.ndim; ++a) {
    if (spatial[static_cast<std::size_t>(a)])
      d.spatialAxes.push_back(a);
    else if (d.compAxis < 0)
      d.compAxis = a;
    else
      fail(path, "more than one non-spatial axis (one component axis is read)");
  }
  if (d.spatialAxes.size() != 3)
    fail(path, std::to_string(d.spatialAxes.size()) + " spatial axes (3 are needed)");
  if (d.compAxis >= 0) out.kind = d.kinds[static_cast<std::size_t>(d.compAxis)];
}

// The space's axes -> RAS; returns the space's name.
std::string nrrdSpace(const std::string& path, const NrrdDescription& d, NrrdVolume& out) {
  std::string space = "right-anterior-superior";
  if (const std::string* s = d.field("space")) {
    space = *s;
    if (space == "left-posterior-superior" || space == "LPS") {
      out.spaceToRas = glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
      out.lps = true;
    } else if (space == "left-anterior-superior" || space == "LAS") {
      out.spaceToRas = glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
    } else if (space != "right-anterior-superior" && space != "RAS") {
      fail(path, "space '" + space + "' is not read (RAS, LAS and LPS are)");
    }
  } else if (d.spaceDirs) {
    out.header.warnings.emplace_back("no 'space' field: space directions taken as RAS");
  }
  return space;
}

// The grid (voxel -> world RAS) and the header facts shown by `info`.
void nrrdGeometry(const std::string& path, const NrrdDescription& d, NrrdVolume& out) {
  VolumeHeader& h = out.header;
  const std::string space = nrrdSpace(path, d, out);
  const glm::dmat3 toRas = out.spaceToRas;
  glm::dvec3 origin(0.0);
  if (const std::string* o = d.field("space origin")) {
    if (!parseVector(path, "space origin", trim(*o), origin)) fail(path, "'space origin' is none");
  }
  glm::dmat4 affine(1.0);
  glm::ivec3 gdims;
  for (int c = 0; c < 3; ++c) {
    const auto a = static_cast<std::size_t>(d.spatialAxes[static_cast<std::size_t>(c)]);
    if (d.sizes[a] > std::numeric_limits<int>::max()) fail(path, "a size is absurd");
    gdims[c] = static_cast<int>(d.sizes[a]);
    affine[c] = glm::dvec4(toRas * d.dirs[a], 0.0);
  }
  affine[3] = glm::dvec4(toRas * origin, 1.0);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(affine[c][r])) fail(path, "the space directions or the space origin are not finite");
  if (singular(glm::dmat3(affine)))
    fail(path, "the space directions are singular (they do not span 3D space): no voxel-to-world affine");
  h.grid = Grid::fromAffine(gdims, affine);
  // Dimensions in the canonical order (i, j, k, components); the header's own order is kept in intentName.
  h.dims = {gdims.x, gdims.y, gdims.z};
  if (d.compAxis >= 0) h.dims.push_back(d.sizes[static_cast<std::size_t>(d.compAxis)]);
  h.datatypeName = *d.field("type");
  h.affineSource = std::string(d.spaceDirs ? "space directions + origin" : "spacings") + " in " + space;
  std::string stored;
  for (long long sz : d.sizes)
    stored += (stored.empty() ? "" : "x") + std::to_string(sz);
  h.intentName = (out.kind.empty() ? "" : "kind " + out.kind + ", ") + "sizes as stored " + stored;
  // Symmetric-matrix kinds are tensors, as NIfTI's SYMMATRIX intent says (what `info` looks for).
  if (out.kind == "3D-symmetric-matrix" || out.kind == "3D-masked-symmetric-matrix" ||
      out.kind == "3D-matrix" || out.kind == "3D-masked-matrix")
    h.intentCode = 1005;
}

void nrrdMeasurementFrame(const std::string& path, const NrrdDescription& d, NrrdVolume& out) {
  const std::string* mf = d.field("measurement frame");
  if (!mf) return;
  const std::vector<std::string> e = vectorEntries(*mf);
  if (e.size() != 3)
    fail(path, "'measurement frame' has " + std::to_string(e.size()) + " vectors (3 expected)");
  for (int c = 0; c < 3; ++c) {
    glm::dvec3 v;
    if (!parseVector(path, "measurement frame", e[static_cast<std::size_t>(c)], v))
      fail(path, "'measurement frame' vector is none");
    out.measurementFrame[c] = v; // columns
  }
  // A singular frame would flatten every tensor silently (D = M D M^T loses a dimension).
  if (singular(out.measurementFrame))
    fail(path, "the measurement frame " + trim(*mf) +
                   " is singular (its vectors do not span 3D space): tensors cannot be taken to world space");
  const glm::dmat3 g = glm::transpose(out.measurementFrame) * out.measurementFrame;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(g[c][r] - (c == r ? 1.0 : 0.0)) > 1e-3) {
        out.header.warnings.push_back("the measurement frame " + trim(*mf) +
                                      " is not a rotation: tensors are transformed by it as given");
        c = 3;
        break;
      }
  out.hasMeasurementFrame = true;
}

// How the data are stored.
struct NrrdEncoding {
  bool big = false, gz = false, ascii = false;
};

NrrdEncoding nrrdEncoding(const std::string& path, const NrrdDescription& d) {
  NrrdEncoding e;
  const std::string encoding = *d.field("encoding");
  const std::string* endian = d.field("endian");
  e.big = endian && *endian == "big";
  if (endian && *endian != "big" && *endian != "little")
    fail(path, "endian '" + *endian + "' is neither little nor big");
  e.gz = encoding == "gzip" || encoding == "gz";
  e.ascii = encoding == "ascii" || encoding == "text" || encoding == "txt";
  if (!e.gz && !e.ascii && encoding != "raw")
    fail(path, "encoding '" + encoding + "' is not read (raw, gzip and ascii are)");
  return e;
}

// The detached data file named by 'data file', or "" when the data are attached.
std::string nrrdDataFile(const std::string& path, const NrrdDescription& d) {
  const std::string* df = d.field("data file", "datafile");
  if (!df) {
    if (!d.blank) fail(path, "no blank line after the header and no 'data file' (truncated file?)");
    return "";
  }
  const std::string name = trim(*df);
  if (name.rfind("LIST", 0) == 0 || name.find('%') != std::string::npos || words(name).size() > 1)
    fail(path, "data file '" + name + "': multi-file data are not read");
  const std::string dataPath =
      fs::path(name).is_absolute() ? name : (fs::path(path).parent_path() / name).string();
  std::error_code ec;
  if (!fs::is_regular_file(dataPath, ec)) fail(path, "data file " + dataPath + " does not exist");
  return dataPath;
}

// A detached data file as stored (a gzip one is inflated later, like attached gzip data).
std::vector<std::uint8_t> readDetached(const std::string& path, const std::string& dataPath) {
  std::error_code ec;
  std::FILE* f = std::fopen(dataPath.c_str(), "rb");
  if (!f) fail(path, "cannot open data file " + dataPath);
  std::vector<std::uint8_t> detached(static_cast<std::size_t>(fs::file_size(dataPath, ec)));
  const bool ok = std::fread(detached.data(), 1, detached.size(), f) == detached.size();
  std::fclose(f);
  if (!ok) fail(path, "cannot read data file " + dataPath);
  return detached;
}

std::vector<double> nrrdAsciiValues(const std::string& path, const std::vector<std::uint8_t>& src,
                                    std::size_t start, long long total) {
  const std::string text(src.begin() + static_cast<std::ptrdiff_t>(std::min(start, src.size())), src.end());
  std::istringstream in(text);
  std::vector<double> values;
  // Each number takes at least two characters with its separator: never reserve beyond what the text holds.
  values.reserve(static_cast<std::size_t>(std::min<long long>(total, static_cast<long long>(text.size() / 2 + 1))));
  double v;
  while (static_cast<long long>(values.size()) < total && in >> v)
    values.push_back(v);
  if (static_cast<long long>(values.size()) < total)
    fail(path, "ascii data hold " + std::to_string(values.size()) + " numbers, the header needs " +
                   std::to_string(total));
  return values;
}

// The binary data: inflated into `inflated` (gzip) or where they lie in `src` (raw), skips applied.
const std::uint8_t* nrrdBinaryData(const std::string& path, const std::vector<std::uint8_t>& src,
                                   std::size_t start, long long byteSkip, bool gz, std::size_t need,
                                   std::vector<std::uint8_t>& inflated) {
  if (gz) {
    if (start > src.size()) fail(path, "the data start beyond the end of the file");
    // The byte skip applies to the inflated data: inflate it and the data after it.
    if (byteSkip < 0) fail(path, "byte skip " + std::to_string(byteSkip) + " is invalid with gzip encoding");
    if (static_cast<unsigned long long>(byteSkip) > (1ULL << 40))
      fail(path, "byte skip " + std::to_string(byteSkip) + " is absurd");
    // One call inflates every gzip member (libdeflate), never far beyond what the header declares; a header
    // declaring more than the stream can hold (or only as a deflate bomb) is refused before allocating.
    const std::size_t declared = need + static_cast<std::size_t>(byteSkip);
    checkInflatable(path, "", src.size() - start, true, declared);
    inflated = inflateGzip(path, src.data() + start, src.size() - start, declared, inflateLimit(declared),
                           "the gzip-encoded data");
    if (byteSkip > 0) {
      // byte skip applies to the decoded data
      if (static_cast<std::size_t>(byteSkip) > inflated.size()) fail(path, "byte skip beyond the data");
      inflated.erase(inflated.begin(), inflated.begin() + byteSkip);
    }
    if (inflated.size() < need)
      fail(path, "is truncated: " + std::to_string(inflated.size()) + " bytes inflated, the header needs " +
                     std::to_string(need));
    return inflated.data();
  }
  std::size_t at = start;
  if (byteSkip == -1) {
    if (src.size() < need) fail(path, "is truncated: the data need " + std::to_string(need) + " bytes");
    at = src.size() - need;
  } else if (byteSkip < 0) {
    fail(path, "byte skip " + std::to_string(byteSkip) + " is invalid");
  } else {
    at += static_cast<std::size_t>(byteSkip);
  }
  if (at > src.size() || src.size() - at < need)
    fail(path, "is truncated: " + std::to_string(at > src.size() ? 0 : src.size() - at) +
                   " data bytes, the header needs " + std::to_string(need));
  return src.data() + at;
}

// The values in stored order into out.volume (components interleaved per voxel).
void nrrdVoxels(const NrrdDescription& d, const NrrdEncoding& e, const std::uint8_t* data,
                const std::vector<double>& values, NrrdVolume& out) {
  const Grid& g = out.header.grid;
  const int comps = d.compAxis >= 0 ? static_cast<int>(d.sizes[static_cast<std::size_t>(d.compAxis)]) : 1;
  out.volume = ScalarVolume(g, comps);
  const SampleTypeInfo& type = *d.type;
  std::vector<long long> idx(static_cast<std::size_t>(d.ndim), 0);
  const auto axis = [&](int a) { return idx[static_cast<std::size_t>(a)]; };
  for (long long n = 0; n < d.total; ++n) {
    const double v = e.ascii ? values[static_cast<std::size_t>(n)] : type.fetch(data + n * type.bytes, e.big);
    const long long c = d.compAxis >= 0 ? axis(d.compAxis) : 0;
    const std::size_t voxel =
        g.index(static_cast<int>(axis(d.spatialAxes[0])), static_cast<int>(axis(d.spatialAxes[1])),
                static_cast<int>(axis(d.spatialAxes[2])));
    out.volume.data[voxel * static_cast<std::size_t>(comps) + static_cast<std::size_t>(c)] =
        static_cast<float>(v);
    for (int a = 0; a < d.ndim; ++a) {
      if (++idx[static_cast<std::size_t>(a)] < d.sizes[static_cast<std::size_t>(a)]) break;
      idx[static_cast<std::size_t>(a)] = 0;
    }
  }
}

// Reads the data described by `d` from `src`, starting at `start` (line and byte skips still to apply).
void readNrrdData(const std::string& path, const NrrdDescription& d, const NrrdEncoding& e,
                  const std::vector<std::uint8_t>& src, std::size_t start, NrrdVolume& out) {
  long long lineSkip = 0, byteSkip = 0;
  if (const std::string* ls = d.field("line skip", "lineskip")) lineSkip = std::atoll(ls->c_str());
  if (const std::string* bs = d.field("byte skip", "byteskip")) byteSkip = std::atoll(bs->c_str());
  for (long long l = 0; l < lineSkip && start < src.size(); ++l) {
    while (start < src.size() && src[start] != '\n')
      ++start;
    ++start;
  }
  const std::size_t need = static_cast<std::size_t>(d.total * d.type->bytes);
  std::vector<std::uint8_t> inflated;
  const std::uint8_t* data = nullptr;
  std::vector<double> values;
  if (e.ascii)
    values = nrrdAsciiValues(path, src, start, d.total);
  else
    data = nrrdBinaryData(path, src, start, byteSkip, e.gz, need, inflated);
  nrrdVoxels(d, e, data, values, out);
}

} // namespace

NrrdVolume readNrrd(const std::string& path, bool withData) {
  NrrdVolume out;
  out.header.path = path;
  out.header.niftiVersion = 0;
  const std::vector<std::uint8_t> bytes = readFileBytes(path, nullptr, std::size_t(1) << 33);
  NrrdDescription d;
  parseNrrdFields(path, bytes, d);
  nrrdSizes(path, d);
  nrrdAxes(path, d, out);
  nrrdGeometry(path, d, out);
  nrrdMeasurementFrame(path, d, out);
  const NrrdEncoding e = nrrdEncoding(path, d);
  const std::string dataPath = nrrdDataFile(path, d);
  if (!withData) {
    const std::size_t need = static_cast<std::size_t>(d.total * d.type->bytes);
    if (dataPath.empty() && !e.gz && !e.ascii && bytes.size() - d.headerEnd < need)
      fail(path, "is truncated: " + std::to_string(bytes.size() - d.headerEnd) +
                     " data bytes, the header needs " + std::to_string(need));
    if (dataPath.empty() && e.gz) checkInflatable(path, "", bytes.size() - d.headerEnd, true, need);
    return out;
  }
  if (dataPath.empty())
    readNrrdData(path, d, e, bytes, d.headerEnd, out);
  else
    readNrrdData(path, d, e, readDetached(path, dataPath), 0, out);
  return out;
}

LoadedTensors nrrdTensors(const std::string& path) {
  NrrdVolume n = readNrrd(path, true);
  const bool masked = n.kind == "3D-masked-symmetric-matrix";
  const bool full = n.kind == "3D-matrix" || n.kind == "3D-masked-matrix";
  const bool fullMasked = n.kind == "3D-masked-matrix";
  if (n.kind != "3D-symmetric-matrix" && !masked && !full)
    fail(path,
         "is not a tensor NRRD: the component axis has kind '" + n.kind +
             "' (3D-symmetric-matrix, 3D-masked-symmetric-matrix, 3D-matrix or 3D-masked-matrix expected)");
  const int want = full ? (fullMasked ? 10 : 9) : masked ? 7 : 6;
  if (n.volume.components != want)
    fail(path, "kind " + n.kind + " needs " + std::to_string(want) + " components, the axis has " +
                   std::to_string(n.volume.components));
  LoadedTensors out;
  out.header = n.header;
  out.warnings = n.header.warnings;
  out.layout = TensorLayout::Fsl; // component order xx xy xz yy yz zz
  out.layoutReason = "NRRD kind " + n.kind + " (" + (masked || fullMasked ? "confidence, then " : "") +
                     (full ? "row-major 3x3, symmetrised" : "xx xy xz yy yz zz") + "); " +
                     (n.hasMeasurementFrame ? "measurement frame applied (D = M D M^T)"
                                            : "no measurement frame (tensors in the space's axes)") +
                     (n.lps ? ", then LPS -> RAS" : "");
  if (!n.hasMeasurementFrame)
    out.warnings.emplace_back("no measurement frame: tensors taken to be in the space's axes");
  const glm::dmat3 r = n.spaceToRas * n.measurementFrame;
  out.field = makeTensorField(n.header.grid);
  const std::size_t nv = n.header.grid.voxelCount();
  std::size_t masked0 = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    const float* c = &n.volume.data[i * static_cast<std::size_t>(want)];
    if (full) {
      // Row-major 3x3 (ITK writes diffusion tensors this way too), symmetrised.
      if (fullMasked && !(c[0] >= 0.5f)) {
        ++masked0;
        continue;
      }
      const float* f = fullMasked ? c + 1 : c;
      glm::dmat3 d;
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
          d[col][row] = 0.5 * (double(f[row * 3 + col]) + double(f[col * 3 + row]));
      storeWorldTensor(out, i, r * d * glm::transpose(r));
      continue;
    }
    if (masked) {
      if (!(c[0] >= 0.5f)) {
        ++masked0;
        continue;
      }
      ++c;
    }
    glm::dmat3 d;
    d[0][0] = c[0];
    d[0][1] = d[1][0] = c[1];
    d[0][2] = d[2][0] = c[2];
    d[1][1] = c[3];
    d[1][2] = d[2][1] = c[4];
    d[2][2] = c[5];
    storeWorldTensor(out, i, r * d * glm::transpose(r));
  }
  if (masked || fullMasked)
    out.layoutReason += "; " + std::to_string(masked0) + " voxels with confidence < 0.5 masked out";
  if (out.nanVoxels)
    out.warnings.push_back(std::to_string(out.nanVoxels) + " voxel(s) hold NaN/Inf values (marked invalid)");
  return out;
}

} // namespace dtf::io::detail

namespace dtf::io::detail {

void writeNrrdTensors(const std::string& path, const TensorField& field) {
  const std::size_t nv = field.grid.voxelCount();
  if (field.tensors.size() != nv || field.valid.size() != nv)
    throw InputError("cannot write " + path + ": tensor field size does not match its grid");
  const Grid& g = field.grid;
  auto vec = [](const glm::dvec3& v) {
    std::ostringstream o;
    o.precision(17);
    o << "(" << v.x << "," << v.y << "," << v.z << ")";
    return o.str();
  };
  // Attached header, RAS space, identity measurement frame (the tensors are world tensors), the tensor
  // axis first with a confidence of 1 where a tensor is valid, 0 elsewhere; gzip-encoded float32.
  std::string h = "NRRD0005\n# written by dtfabric: world RAS tensors, mm^2/s\ntype: float\ndimension: 4\n";
  h += "sizes: 7 " + std::to_string(g.dims.x) + " " + std::to_string(g.dims.y) + " " +
       std::to_string(g.dims.z) + "\n";
  h += "kinds: 3D-masked-symmetric-matrix space space space\nspace: right-anterior-superior\n";
  h += "space directions: none " + vec(glm::dvec3(g.voxelToWorld[0])) + " " +
       vec(glm::dvec3(g.voxelToWorld[1])) + " " + vec(glm::dvec3(g.voxelToWorld[2])) + "\n";
  h += "space origin: " + vec(glm::dvec3(g.voxelToWorld[3])) + "\n";
  h += "measurement frame: (1,0,0) (0,1,0) (0,0,1)\nendian: little\nencoding: gzip\n\n";
  std::vector<float> values(nv * 7, 0.0f);
  for (std::size_t i = 0; i < nv; ++i) {
    if (!field.valid[i]) continue;
    const auto c = field.tensors[i].components(); // xx xy xz yy yz zz, teem's order
    values[i * 7] = 1.0f;
    for (int k = 0; k < 6; ++k)
      values[i * 7 + 1 + static_cast<std::size_t>(k)] = c[static_cast<std::size_t>(k)];
  }
  // Header as plain text, then one gzip member of the values (teem's attached gzip layout).
  const std::vector<std::uint8_t> z =
      gzipCompress(reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(float));
  std::vector<std::uint8_t> out(h.begin(), h.end());
  out.insert(out.end(), z.begin(), z.end());
  writeFileBytes(path, out, false);
}

} // namespace dtf::io::detail
