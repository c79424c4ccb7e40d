// MRtrix image format (.mif, .mif.gz, .mih + data file), as MRtrix3 writes it: a text header
//   mrtrix image / dim / vox / layout / datatype / transform (3 rows) / [scaling] / [dw_scheme ...] / file
// ended by "END", then the data at the `file` offset (the same file when the name is ".").
//
// Geometry. The voxel index (i, j, k) counts along the axes in `dim` order. `transform` is a 3x4 matrix
// [R | t] whose rotation columns are unit vectors; the voxel -> scanner (world RAS mm) affine is
// [R * diag(vox) | t]. `layout` only says how the voxels lie in the file: one signed rank per axis, the
// axis with the smallest |rank| varies fastest, and a negative sign means the axis is stored in reverse
// (index 0 of that axis is the last one on disk). So a file converted from an LAS NIfTI holds an RAS
// transform with layout -0,+1,+2: the bytes are those of the NIfTI, the index order is flipped in i.
// Values are offset + scale * stored (`scaling: offset,scale`). Bit images pack 8 voxels per byte, the
// first voxel in the most significant bit (MRtrix's BITMASK >> (i % 8)).
#include "io/formats/format_detail.h"
#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <sstream>

namespace fs = std::filesystem;

namespace dtf::io::detail {

namespace {


std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, ','))
    out.push_back(trim(item));
  return out;
}

double parseNumber(const std::string& path, const std::string& key, const std::string& text) {
  const std::string t = trim(text);
  if (t == "nan" || t == "NaN") return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size()) fail(path, "'" + key + "' holds '" + t + "', not a number");
  return v;
}

std::vector<double> parseNumbers(const std::string& path, const std::string& key, const std::string& text) {
  std::vector<double> out;
  for (const std::string& s : splitList(text))
    out.push_back(parseNumber(path, key, s));
  return out;
}

struct DataType {
  std::string name;
  int bytes = 4; // 0 for Bit
  bool isFloat = false;
  bool isSigned = true;
  bool bigEndian = false;
};

DataType parseDatatype(const std::string& path, const std::string& text) {
  DataType d;
  d.name = text;
  std::string t = text;
  if (t == "Bit") {
    d.bytes = 0;
    d.isSigned = false;
    return d;
  }
  if (endsWith(t, "LE") || endsWith(t, "BE")) {
    d.bigEndian = endsWith(t, "BE");
    t.resize(t.size() - 2);
  }
  static const struct {
    const char* n;
    int bytes;
    bool f, s;
  } kTypes[] = {{"Int8", 1, false, true},    {"UInt8", 1, false, false},  {"Int16", 2, false, true},
                {"UInt16", 2, false, false}, {"Int32", 4, false, true},   {"UInt32", 4, false, false},
                {"Int64", 8, false, true},   {"UInt64", 8, false, false}, {"Float32", 4, true, true},
                {"Float64", 8, true, true}};
  for (const auto& k : kTypes)
    if (t == k.n) {
      d.bytes = k.bytes;
      d.isFloat = k.f;
      d.isSigned = k.s;
      return d;
    }
  fail(path, "unsupported datatype '" + text +
                 "' (supported: Bit, Int8/16/32/64, UInt8/16/32/64, Float32/64 with LE/BE; complex is not)");
}

// One value of `d` at byte position p, as double.
double fetch(const std::uint8_t* p, const DataType& d) {
  return fetchNumber(p, d.bytes, d.isFloat, d.isSigned, d.bigEndian);
}

// Parses "+0,-1,+2" into signed 1-based ranks (+1, -2, +3).
std::vector<int> parseLayout(const std::string& path, const std::string& text, std::size_t ndim) {
  std::vector<int> out;
  for (const std::string& s : splitList(text)) {
    if (s.size() < 2 || (s[0] != '+' && s[0] != '-') ||
        s.find_first_not_of("0123456789", 1) != std::string::npos || s.size() > 4)
      fail(path, "bad layout entry '" + s + "' (expected e.g. +0,-1,+2)");
    const int rank = std::stoi(s.substr(1)) + 1;
    out.push_back(s[0] == '-' ? -rank : rank);
  }
  if (out.size() != ndim)
    fail(path, "layout has " + std::to_string(out.size()) + " entries for " + std::to_string(ndim) + " axes");
  std::vector<int> ranks;
  for (int r : out)
    ranks.push_back(std::abs(r));
  std::sort(ranks.begin(), ranks.end());
  if (std::adjacent_find(ranks.begin(), ranks.end()) != ranks.end())
    fail(path, "layout '" + text + "' gives two axes the same rank");
  return out;
}

// Element strides (signed) and the offset of index 0, from signed ranks.
void computeStrides(const std::vector<long long>& dims, const std::vector<int>& ranks,
                    std::vector<long long>& strides, long long& start) {
  const std::size_t n = dims.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return std::abs(ranks[a]) < std::abs(ranks[b]); });
  strides.assign(n, 0);
  long long s = 1;
  start = 0;
  for (std::size_t a : order) {
    strides[a] = ranks[a] < 0 ? -s : s;
    if (ranks[a] < 0) start += (dims[a] - 1) * s;
    s *= dims[a];
  }
}

} // namespace

MrtrixImage readMrtrix(const std::string& path, bool withData) {
  MrtrixImage img;
  VolumeHeader& h = img.header;
  h.path = path;
  h.niftiVersion = 0;
  bool gz = false;
  // .mif.gz files hold header and data in one gzip stream: the whole file is inflated for the data, its
  // first MiB for the header alone.
  std::error_code ec;
  if (!withData && !fs::is_regular_file(path, ec)) readFileBytes(path); // throws the reason
  const std::vector<std::uint8_t> bytes = withData ? readFileBytes(path, &gz) : peekFileBytes(path, 1 << 20);
  if (!withData) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    unsigned char m[2] = {0, 0};
    if (f) {
      gz = std::fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
      std::fclose(f);
    }
  }
  const std::string kMagic = "mrtrix image";
  if (bytes.size() < kMagic.size() || std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    fail(path, "not an MRtrix image (no 'mrtrix image' line at the start)");
  // Header lines up to END (at most 1 MiB of header).
  const std::size_t headerLimit = std::min<std::size_t>(bytes.size(), std::size_t(1) << 20);
  std::size_t pos = 0;
  bool ended = false;
  std::vector<long long> dims;
  std::vector<double> vox;
  std::vector<int> ranks;
  std::string datatypeText, layoutText;
  std::vector<std::vector<double>> transform;
  std::vector<std::string> files;
  double offset = 0, scale = 1;
  int lineNo = 0;
  while (pos < headerLimit) {
    std::size_t eol = pos;
    while (eol < headerLimit && bytes[eol] != '\n')
      ++eol;
    if (eol == headerLimit) break;
    const std::string line = trim(std::string(bytes.begin() + static_cast<std::ptrdiff_t>(pos),
                                              bytes.begin() + static_cast<std::ptrdiff_t>(eol)));
    pos = eol + 1;
    if (++lineNo == 1) {
      if (line != kMagic) fail(path, "not an MRtrix image (first line is '" + line.substr(0, 40) + "')");
      continue;
    }
    if (line == "END") {
      ended = true;
      break;
    }
    if (line.empty()) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos)
      fail(path, "header line " + std::to_string(lineNo) + " has no 'key: value'");
    const std::string key = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if (key == "dim") {
      for (double d : parseNumbers(path, key, value)) {
        if (!(d >= 1) || d != std::floor(d) || d > double(kMaxValues))
          fail(path, "dim '" + value + "': every dimension must be a whole number >= 1");
        dims.push_back(static_cast<long long>(d));
      }
    } else if (key == "vox") {
      vox = parseNumbers(path, key, value);
    } else if (key == "layout") {
      layoutText = value;
    } else if (key == "datatype") {
      datatypeText = value;
    } else if (key == "transform") {
      transform.push_back(parseNumbers(path, key, value));
    } else if (key == "scaling") {
      const std::vector<double> s = parseNumbers(path, key, value);
      if (s.size() != 2 || !std::isfinite(s[0]) || !std::isfinite(s[1]))
        fail(path, "scaling '" + value + "' is not two finite numbers (offset,scale)");
      offset = s[0];
      scale = s[1];
    } else if (key == "file") {
      files.push_back(value);
    } else if (key == "dw_scheme") {
      img.dwScheme.push_back(parseNumbers(path, key, value));
    } else if (key == "comments" && h.descrip.empty()) {
      h.descrip = value;
    }
  }
  if (!ended) fail(path, "the header has no END line (truncated file?)");
  if (dims.empty()) fail(path, "the header has no 'dim'");
  if (dims.size() > 16) fail(path, std::to_string(dims.size()) + " dimensions (at most 16 are read)");
  long long total = 1;
  for (long long d : dims) {
    if (total > kMaxValues / d)
      fail(path, "dimensions are absurd (more than 2^31 values); refusing to allocate");
    total *= d;
  }
  if (vox.size() < std::min<std::size_t>(3, dims.size()))
    fail(path,
         "'vox' has " + std::to_string(vox.size()) + " entries for " + std::to_string(dims.size()) + " axes");
  if (datatypeText.empty()) fail(path, "the header has no 'datatype'");
  const DataType dt = parseDatatype(path, datatypeText);
  if (layoutText.empty()) fail(path, "the header has no 'layout'");
  ranks = parseLayout(path, layoutText, dims.size());
  if (files.empty()) fail(path, "the header has no 'file' entry");
  if (files.size() > 1)
    fail(path, "the data are split over " + std::to_string(files.size()) + " files (not supported)");

  // Geometry: spatial axes 0..2 (missing ones are 1), transform [R | t] with R scaled by vox.
  glm::ivec3 gdims(1);
  glm::dvec3 spacing(1.0);
  for (std::size_t d = 0; d < 3 && d < dims.size(); ++d) {
    if (dims[d] > std::numeric_limits<int>::max())
      fail(path, "dimension " + std::to_string(d) + " is absurd");
    gdims[static_cast<int>(d)] = static_cast<int>(dims[d]);
    if (!(vox[d] > 0) || !std::isfinite(vox[d]))
      fail(path,
           "voxel size " + std::to_string(vox[d]) + " along axis " + std::to_string(d) + " is not positive");
    spacing[static_cast<int>(d)] = vox[d];
  }
  glm::dmat4 affine(1.0);
  if (transform.empty()) {
    for (int d = 0; d < 3; ++d) {
      affine[d][d] = spacing[d];
      affine[3][d] = -0.5 * (gdims[d] - 1) * spacing[d];
    }
    h.affineSource = "none (MRtrix default: identity rotation, image centred)";
    h.warnings.emplace_back("no transform in the header: orientation unknown, assuming RAS voxel axes");
  } else {
    if (transform.size() != 3 && !(transform.size() == 4 && transform[3].size() == 4))
      fail(path, "'transform' has " + std::to_string(transform.size()) + " rows (expected 3)");
    for (int r = 0; r < 3; ++r) {
      if (transform[static_cast<std::size_t>(r)].size() != 4)
        fail(path, "'transform' row " + std::to_string(r + 1) + " has " +
                       std::to_string(transform[static_cast<std::size_t>(r)].size()) +
                       " numbers (expected 4)");
      for (int c = 0; c < 4; ++c) {
        const double v = transform[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
        if (!std::isfinite(v)) fail(path, "'transform' is not finite");
        affine[c][r] = c < 3 ? v * spacing[c] : v;
      }
    }
    h.affineSource = "MRtrix transform (scanner frame) x vox";
    if (std::abs(glm::determinant(glm::dmat3(affine))) < 1e-12) fail(path, "the transform is singular");
  }
  h.grid = Grid::fromAffine(gdims, affine);
  h.dims = dims;
  h.datatypeName = dt.name;
  h.sclInter = offset;
  h.sclSlope = scale;
  h.intentName = "layout " + layoutText;

  // Data location.
  std::string dataPath = path;
  long long dataOffset = 0;
  {
    std::istringstream in(files[0]);
    std::string name;
    in >> name;
    std::string offText;
    if (in >> offText) {
      // Fuzz finding: "file: . nan" was converted to an integer (undefined behaviour).
      const double off = parseNumber(path, "file", offText);
      if (!(off >= 0) || off > 0x1p62 || off != std::floor(off))
        fail(path, "file offset " + offText + " is not a whole number >= 0");
      dataOffset = static_cast<long long>(off);
    }
    if (name != ".") {
      if (name.find('/') == 0) fail(path, "data file '" + name + "' is an absolute path (refused)");
      dataPath = (fs::path(path).parent_path() / name).string();
    }
  }
  const long long need = dt.bytes == 0 ? (total + 7) / 8 : total * dt.bytes;
  std::vector<std::uint8_t> dataBytes;
  const std::vector<std::uint8_t>* data = &bytes;
  if (dataPath != path) {
    if (!fs::exists(dataPath)) fail(path, "data file " + dataPath + " does not exist");
    if (withData) {
      dataBytes = readFileBytes(dataPath);
      data = &dataBytes;
    } else {
      const auto size = static_cast<long long>(fs::file_size(dataPath, ec));
      if (!ec && size < dataOffset + need && !endsWith(dataPath, ".gz"))
        fail(path, "data file " + dataPath + " is truncated: " + std::to_string(size) +
                       " bytes, the header needs " + std::to_string(dataOffset + need));
    }
  } else if (dataOffset < static_cast<long long>(pos)) {
    fail(path, "file offset " + std::to_string(dataOffset) + " lies inside the header (which ends at byte " +
                   std::to_string(pos) + ")");
  }
  long long have = static_cast<long long>(data->size());
  if (!withData && dataPath == path) {
    const auto size = fs::file_size(path, ec);
    have = gz || ec ? std::numeric_limits<long long>::max() : static_cast<long long>(size);
  }
  if ((withData || dataPath == path) && have < dataOffset + need)
    fail(path, std::string(dataPath == path ? "" : "data file " + dataPath + " ") + "is truncated: " +
                   std::to_string(have) + (gz ? " bytes inflated" : " bytes") + ", the header needs " +
                   std::to_string(dataOffset + need) + " (offset " + std::to_string(dataOffset) + ")");
  if (!img.dwScheme.empty()) {
    const long long vols =
        dims.size() > 3 ? total / (static_cast<long long>(gdims.x) * gdims.y * gdims.z) : 1;
    for (const auto& row : img.dwScheme)
      if (row.size() != 4)
        fail(path, "a dw_scheme row has " + std::to_string(row.size()) + " numbers (expected 4)");
    if (static_cast<long long>(img.dwScheme.size()) != vols)
      fail(path, "dw_scheme has " + std::to_string(img.dwScheme.size()) + " rows for " +
                     std::to_string(vols) + " volumes");
  }
  if (!withData) return img;

  std::vector<long long> strides;
  long long start = 0;
  computeStrides(dims, ranks, strides, start);
  const long long nv = static_cast<long long>(gdims.x) * gdims.y * gdims.z;
  const int comps = static_cast<int>(total / nv);
  img.volume = ScalarVolume(h.grid, comps);
  const std::uint8_t* base = data->data() + dataOffset;
  const bool scaled = !(offset == 0 && scale == 1);
  std::vector<long long> idx(dims.size(), 0);
  long long diskPos = start;
  // Walk logical indices (axis 0 fastest), tracking the disk position incrementally.
  for (long long n = 0; n < total; ++n) {
    double v;
    if (dt.bytes == 0)
      v = (base[diskPos >> 3] >> (7 - (diskPos & 7))) & 1;
    else
      v = fetch(base + diskPos * dt.bytes, dt);
    if (scaled) v = offset + scale * v;
    const long long voxel = n % nv, comp = n / nv;
    img.volume.data[static_cast<std::size_t>(voxel * comps + comp)] = static_cast<float>(v);
    for (std::size_t a = 0; a < dims.size(); ++a) {
      if (++idx[a] < dims[a]) {
        diskPos += strides[a];
        break;
      }
      diskPos -= strides[a] * (dims[a] - 1);
      idx[a] = 0;
    }
  }
  return img;
}

void writeMrtrix(const std::string& path, const ScalarVolume& v, const std::vector<int>& stridesIn,
                 const std::vector<std::string>& extraHeader) {
  const std::size_t nv = v.grid.voxelCount();
  if (v.components < 1 || v.data.size() != nv * static_cast<std::size_t>(v.components))
    throw InputError("cannot write " + path + ": volume data size does not match its grid");
  const bool mih = endsWith(path, ".mih");
  const bool gz = endsWith(path, ".mif.gz");
  if (!mih && !gz && !endsWith(path, ".mif"))
    throw InputError("cannot write " + path + ": an MRtrix image name ends in .mif, .mif.gz or .mih");
  std::vector<long long> dims{v.grid.dims.x, v.grid.dims.y, v.grid.dims.z};
  if (v.components > 1) dims.push_back(v.components);
  std::vector<int> ranks = stridesIn;
  if (ranks.empty())
    for (std::size_t a = 0; a < dims.size(); ++a)
      ranks.push_back(static_cast<int>(a) + 1);
  if (ranks.size() < dims.size())
    throw InputError("cannot write " + path + ": " + std::to_string(ranks.size()) + " strides for " +
                     std::to_string(dims.size()) + " axes");
  ranks.resize(dims.size());
  {
    std::vector<int> r;
    for (int x : ranks)
      r.push_back(std::abs(x));
    std::sort(r.begin(), r.end());
    if (r.front() == 0 || std::adjacent_find(r.begin(), r.end()) != r.end())
      throw InputError("cannot write " + path + ": strides must be distinct non-zero ranks");
  }
  std::ostringstream hd;
  hd.precision(17);
  hd << "mrtrix image\ndim: ";
  for (std::size_t a = 0; a < dims.size(); ++a)
    hd << (a ? "," : "") << dims[a];
  hd << "\nvox: " << v.grid.spacing.x << "," << v.grid.spacing.y << "," << v.grid.spacing.z;
  if (dims.size() > 3) hd << ",nan";
  // Ranks are written 0-based in the order of their size, keeping the signs.
  std::vector<int> sorted;
  for (int x : ranks)
    sorted.push_back(std::abs(x));
  std::sort(sorted.begin(), sorted.end());
  hd << "\nlayout: ";
  for (std::size_t a = 0; a < dims.size(); ++a) {
    const auto rank = std::find(sorted.begin(), sorted.end(), std::abs(ranks[a])) - sorted.begin();
    hd << (a ? "," : "") << (ranks[a] < 0 ? "-" : "+") << rank;
  }
  hd << "\ndatatype: Float32LE\n";
  for (int r = 0; r < 3; ++r) {
    hd << "transform: ";
    for (int c = 0; c < 4; ++c)
      hd << (c ? "," : "")
         << (c < 3 ? v.grid.voxelToWorld[c][r] / v.grid.spacing[c] : v.grid.voxelToWorld[3][r]);
    hd << "\n";
  }
  for (const std::string& line : extraHeader)
    hd << line << "\n";
  std::string head = hd.str();

  std::vector<long long> strides;
  long long start = 0;
  computeStrides(dims, ranks, strides, start);
  std::vector<float> disk(nv * static_cast<std::size_t>(v.components));
  {
    std::vector<long long> idx(dims.size(), 0);
    long long diskPos = start;
    const long long total = static_cast<long long>(disk.size());
    for (long long n = 0; n < total; ++n) {
      const long long voxel = n % static_cast<long long>(nv), comp = n / static_cast<long long>(nv);
      disk[static_cast<std::size_t>(diskPos)] = v.data[static_cast<std::size_t>(voxel * v.components + comp)];
      for (std::size_t a = 0; a < dims.size(); ++a) {
        if (++idx[a] < dims[a]) {
          diskPos += strides[a];
          break;
        }
        diskPos -= strides[a] * (dims[a] - 1);
        idx[a] = 0;
      }
    }
  }
  static_assert(sizeof(float) == 4);
  std::vector<std::uint8_t> dataBytes(disk.size() * 4);
  std::memcpy(dataBytes.data(), disk.data(), dataBytes.size()); // little-endian host (x86-64, aarch64)
  if (mih) {
    const std::string dataName = fs::path(path).stem().string() + ".dat";
    head += "file: " + dataName + " 0\nEND\n";
    writeFileBytes((fs::path(path).parent_path() / dataName).string(), dataBytes, false);
    writeFileBytes(path, std::vector<std::uint8_t>(head.begin(), head.end()), false);
    return;
  }
  // "file: . OFFSET" with the offset past the END line, aligned to 16 bytes; the offset's digits change
  // the header length, so iterate until it is stable.
  std::size_t off = 0;
  std::string full;
  for (int it = 0; it < 4; ++it) {
    full = head + "file: . " + std::to_string(off) + "\nEND\n";
    const std::size_t need = (full.size() + 15) / 16 * 16;
    if (need == off) break;
    off = need;
  }
  full.resize(off, '\0');
  std::vector<std::uint8_t> out(full.begin(), full.end());
  out.insert(out.end(), dataBytes.begin(), dataBytes.end());
  writeFileBytes(path, out, gz);
}

} // namespace dtf::io::detail
