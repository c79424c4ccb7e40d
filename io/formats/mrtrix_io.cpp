// SPDX-License-Identifier: GPL-3.0-or-later
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
#include "io/formats/atomic_file.h"
#include "io/formats/format_detail.h"
#include "io/formats/gzip.h"
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
  SampleType type = SampleType::Float32;
  bool bigEndian = false;
};

DataType parseDatatype(const std::string& path, const std::string& text) {
  DataType d;
  d.name = text;
  std::string t = text;
  if (t == "Bit") {
    d.bytes = 0;
    return d;
  }
  if (endsWith(t, "LE") || endsWith(t, "BE")) {
    d.bigEndian = endsWith(t, "BE");
    t.resize(t.size() - 2);
  }
  // MRtrix's names are those of the sample table.
  for (int k = 0; k <= static_cast<int>(SampleType::Float64); ++k)
    if (t == sampleTypeInfo(static_cast<SampleType>(k)).name) {
      d.type = static_cast<SampleType>(k);
      d.bytes = sampleTypeInfo(d.type).bytes;
      return d;
    }
  fail(path, "unsupported datatype '" + text +
                 "' (supported: Bit, Int8/16/32/64, UInt8/16/32/64, Float32/64 with LE/BE; complex is not)");
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

// The next logical index (axis 0 fastest) and the disk position that goes with it.
void step(std::vector<long long>& idx, const std::vector<long long>& dims,
          const std::vector<long long>& strides, long long& diskPos) {
  for (std::size_t a = 0; a < dims.size(); ++a) {
    if (++idx[a] < dims[a]) {
      diskPos += strides[a];
      return;
    }
    diskPos -= strides[a] * (dims[a] - 1);
    idx[a] = 0;
  }
}

// The header of an MRtrix image as written, before any geometry is derived from it.
struct MrtrixDescription {
  std::vector<long long> dims;
  std::vector<double> vox;
  std::string datatypeText, layoutText;
  std::vector<std::vector<double>> transform;
  std::vector<std::string> files;
  double offset = 0, scale = 1;
  std::size_t headerEnd = 0; // byte after the END line
};

// The header's bytes: the file's first MiB (inflated). Sets `gz`. The data are read once the header has
// said how many bytes they take (readMrtrix), so a gzip stream is never inflated beyond them.
std::vector<std::uint8_t> mrtrixHeaderBytes(const std::string& path, bool& gz) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) readFileBytes(path); // throws the reason
  std::vector<std::uint8_t> bytes = peekFileBytes(path, 1 << 20);
  gz = startsWithGzipMagic(path);
  // A corrupt gzip stream inflates to nothing here: the full read names the problem.
  if (bytes.empty() && gz) readFileBytes(path);
  return bytes;
}

// The first `need` bytes of `file` (inflated), refused before anything is read when the file cannot hold
// them (a gzip file holds at most kMaxDeflateRatio times its size).
std::vector<std::uint8_t> mrtrixPrefix(const std::string& path, const std::string& file, long long offset,
                                       long long need) {
  checkInflatable(path, file == path ? "" : "data file " + file + " ", file,
                  static_cast<unsigned long long>(offset + need), " (offset " + std::to_string(offset) + ")");
  // A gzip stream (.mif.gz, or a gzip data file) is inflated whole (libdeflate) into the size the header
  // declares and refused when it runs far beyond it; a plain file is read as it is.
  const auto total = static_cast<std::size_t>(offset + need);
  std::vector<std::uint8_t> raw = readRawFile(file);
  if (!isGzip(raw.data(), raw.size())) return raw;
  return inflateGzip(file, raw.data(), raw.size(), total, inflateLimit(total), "the gzip data");
}

// One "key: value" header line into `d` (and the dw_scheme and comments into `img`).
void mrtrixHeaderEntry(const std::string& path, const std::string& key, const std::string& value,
                       MrtrixDescription& d, MrtrixImage& img) {
  if (key == "dim") {
    for (double n : parseNumbers(path, key, value)) {
      if (!(n >= 1) || n != std::floor(n) || n > double(kMaxValues))
        fail(path, "dim '" + value + "': every dimension must be a whole number >= 1");
      d.dims.push_back(static_cast<long long>(n));
    }
  } else if (key == "vox") {
    d.vox = parseNumbers(path, key, value);
  } else if (key == "layout") {
    d.layoutText = value;
  } else if (key == "datatype") {
    d.datatypeText = value;
  } else if (key == "transform") {
    d.transform.push_back(parseNumbers(path, key, value));
  } else if (key == "scaling") {
    const std::vector<double> sc = parseNumbers(path, key, value);
    if (sc.size() != 2 || !std::isfinite(sc[0]) || !std::isfinite(sc[1]))
      fail(path, "scaling '" + value + "' is not two finite numbers (offset,scale)");
    d.offset = sc[0];
    d.scale = sc[1];
  } else if (key == "file") {
    d.files.push_back(value);
  } else if (key == "dw_scheme") {
    img.dwScheme.push_back(parseNumbers(path, key, value));
  } else if (key == "comments" && img.header.descrip.empty()) {
    img.header.descrip = value;
  }
}

// The header lines up to END (at most 1 MiB of header).
MrtrixDescription parseMrtrixHeader(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                    MrtrixImage& img) {
  const std::string kMagic = "mrtrix image";
  if (bytes.size() < kMagic.size() || std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    fail(path, "not an MRtrix image (no 'mrtrix image' line at the start)");
  const std::size_t headerLimit = std::min<std::size_t>(bytes.size(), std::size_t(1) << 20);
  MrtrixDescription d;
  std::size_t pos = 0;
  bool ended = false;
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
    mrtrixHeaderEntry(path, trim(line.substr(0, colon)), trim(line.substr(colon + 1)), d, img);
  }
  if (!ended) fail(path, "the header has no END line (truncated file?)");
  d.headerEnd = pos;
  return d;
}

// The voxel -> world affine: spatial axes 0..2 (missing ones are 1), transform [R | t] with R scaled by vox.
// Sets the grid and the affine source of `h`.
void mrtrixGeometry(const std::string& path, const MrtrixDescription& d, VolumeHeader& h) {
  glm::ivec3 gdims(1);
  glm::dvec3 spacing(1.0);
  for (std::size_t a = 0; a < 3 && a < d.dims.size(); ++a) {
    if (d.dims[a] > std::numeric_limits<int>::max())
      fail(path, "dimension " + std::to_string(a) + " is absurd");
    gdims[static_cast<int>(a)] = static_cast<int>(d.dims[a]);
    if (!(d.vox[a] > 0) || !std::isfinite(d.vox[a]))
      fail(path, "voxel size " + std::to_string(d.vox[a]) + " along axis " + std::to_string(a) +
                     " is not positive");
    spacing[static_cast<int>(a)] = d.vox[a];
  }
  glm::dmat4 affine(1.0);
  const auto& t = d.transform;
  if (t.empty()) {
    for (int a = 0; a < 3; ++a) {
      affine[a][a] = spacing[a];
      affine[3][a] = -0.5 * (gdims[a] - 1) * spacing[a];
    }
    h.affineSource = "none (MRtrix default: identity rotation, image centred)";
    h.warnings.emplace_back("no transform in the header: orientation unknown, assuming RAS voxel axes");
  } else {
    if (t.size() != 3 && !(t.size() == 4 && t[3].size() == 4))
      fail(path, "'transform' has " + std::to_string(t.size()) + " rows (expected 3)");
    for (std::size_t r = 0; r < 3; ++r) {
      if (t[r].size() != 4)
        fail(path, "'transform' row " + std::to_string(r + 1) + " has " + std::to_string(t[r].size()) +
                       " numbers (expected 4)");
      for (int c = 0; c < 4; ++c) {
        const double v = t[r][static_cast<std::size_t>(c)];
        if (!std::isfinite(v)) fail(path, "'transform' is not finite");
        affine[c][static_cast<int>(r)] = c < 3 ? v * spacing[c] : v;
      }
    }
    h.affineSource = "MRtrix transform (scanner frame) x vox";
    if (std::abs(glm::determinant(glm::dmat3(affine))) < 1e-12) fail(path, "the transform is singular");
  }
  h.grid = Grid::fromAffine(gdims, affine);
}

// Checks the dimensions and voxel sizes; returns the number of values.
long long mrtrixValueCount(const std::string& path, const MrtrixDescription& d) {
  if (d.dims.empty()) fail(path, "the header has no 'dim'");
  if (d.dims.size() > 16) fail(path, std::to_string(d.dims.size()) + " dimensions (at most 16 are read)");
  long long total = 1;
  for (long long n : d.dims) {
    if (total > kMaxValues / n)
      fail(path, "dimensions are absurd (more than 2^31 values); refusing to allocate");
    total *= n;
  }
  if (d.vox.size() < std::min<std::size_t>(3, d.dims.size()))
    fail(path, "'vox' has " + std::to_string(d.vox.size()) + " entries for " + std::to_string(d.dims.size()) +
                   " axes");
  return total;
}

// Where the data lie: the file itself ("file: . OFFSET") or a file beside the header.
void mrtrixDataLocation(const std::string& path, const std::string& entry, std::string& dataPath,
                        long long& dataOffset) {
  dataPath = path;
  dataOffset = 0;
  std::istringstream in(entry);
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

// The data's bytes (read into `dataBytes` when withData, never more than the header needs), after checking
// that the data are all there. Null when !withData.
const std::vector<std::uint8_t>* mrtrixData(const std::string& path, const MrtrixDescription& d,
                                            const std::vector<std::uint8_t>& bytes, bool gz, bool withData,
                                            long long need, std::vector<std::uint8_t>& dataBytes,
                                            long long& dataOffset) {
  std::string dataPath;
  mrtrixDataLocation(path, d.files[0], dataPath, dataOffset);
  const std::vector<std::uint8_t>* data = &bytes;
  if (dataPath != path) {
    if (!fs::exists(dataPath)) fail(path, "data file " + dataPath + " does not exist");
    if (withData) {
      dataBytes = mrtrixPrefix(path, dataPath, dataOffset, need);
      data = &dataBytes;
    } else {
      checkInflatable(path, "data file " + dataPath + " ", dataPath,
                      static_cast<unsigned long long>(dataOffset + need),
                      " (offset " + std::to_string(dataOffset) + ")");
    }
  } else if (dataOffset < static_cast<long long>(d.headerEnd)) {
    fail(path, "file offset " + std::to_string(dataOffset) + " lies inside the header (which ends at byte " +
                   std::to_string(d.headerEnd) + ")");
  }
  long long have = static_cast<long long>(data->size());
  if (withData && dataPath == path) {
    dataBytes = mrtrixPrefix(path, path, dataOffset, need);
    data = &dataBytes;
    have = static_cast<long long>(data->size());
  } else if (!withData && dataPath == path) {
    checkInflatable(path, "", path, static_cast<unsigned long long>(dataOffset + need),
                    " (offset " + std::to_string(dataOffset) + ")");
    have = dataOffset + need;
  }
  if ((withData || dataPath == path) && have < dataOffset + need)
    fail(path, std::string(dataPath == path ? "" : "data file " + dataPath + " ") + "is truncated: " +
                   std::to_string(have) + (gz ? " bytes inflated" : " bytes") + ", the header needs " +
                   std::to_string(dataOffset + need) + " (offset " + std::to_string(dataOffset) + ")");
  return withData ? data : nullptr;
}

void checkDwScheme(const std::string& path, const MrtrixImage& img, long long total) {
  if (img.dwScheme.empty()) return;
  const Grid& g = img.header.grid;
  const long long vols =
      img.header.dims.size() > 3 ? total / (static_cast<long long>(g.dims.x) * g.dims.y * g.dims.z) : 1;
  for (const auto& row : img.dwScheme)
    if (row.size() != 4)
      fail(path, "a dw_scheme row has " + std::to_string(row.size()) + " numbers (expected 4)");
  if (static_cast<long long>(img.dwScheme.size()) != vols)
    fail(path, "dw_scheme has " + std::to_string(img.dwScheme.size()) + " rows for " + std::to_string(vols) +
                   " volumes");
}

// The voxels into img.volume: logical indices walked with axis 0 fastest, the disk position tracked
// incrementally through the layout's strides; axes 3.. become components.
void readMrtrixVoxels(const MrtrixDescription& d, const DataType& dt, const std::vector<int>& ranks,
                      const std::uint8_t* base, long long total, MrtrixImage& img) {
  const std::vector<long long>& dims = d.dims;
  std::vector<long long> strides;
  long long start = 0;
  computeStrides(dims, ranks, strides, start);
  const long long nv = static_cast<long long>(img.header.grid.voxelCount());
  const int comps = static_cast<int>(total / nv);
  img.volume = ScalarVolume(img.header.grid, comps);
  const bool scaled = !(d.offset == 0 && d.scale == 1);
  std::vector<long long> idx(dims.size(), 0);
  long long diskPos = start;
  for (long long n = 0; n < total; ++n) {
    double v;
    if (dt.bytes == 0)
      v = (base[diskPos >> 3] >> (7 - (diskPos & 7))) & 1;
    else
      v = fetchSample(base + diskPos * dt.bytes, dt.type, dt.bigEndian);
    if (scaled) v = d.offset + d.scale * v;
    const long long voxel = n % nv, comp = n / nv;
    img.volume.data[static_cast<std::size_t>(voxel * comps + comp)] = static_cast<float>(v);
    step(idx, dims, strides, diskPos);
  }
}

} // namespace

MrtrixImage readMrtrix(const std::string& path, bool withData) {
  MrtrixImage img;
  VolumeHeader& h = img.header;
  h.path = path;
  h.niftiVersion = 0;
  bool gz = false;
  const std::vector<std::uint8_t> bytes = mrtrixHeaderBytes(path, gz);
  const MrtrixDescription d = parseMrtrixHeader(path, bytes, img);
  const long long total = mrtrixValueCount(path, d);
  if (d.datatypeText.empty()) fail(path, "the header has no 'datatype'");
  const DataType dt = parseDatatype(path, d.datatypeText);
  if (d.layoutText.empty()) fail(path, "the header has no 'layout'");
  const std::vector<int> ranks = parseLayout(path, d.layoutText, d.dims.size());
  if (d.files.empty()) fail(path, "the header has no 'file' entry");
  if (d.files.size() > 1)
    fail(path, "the data are split over " + std::to_string(d.files.size()) + " files (not supported)");
  mrtrixGeometry(path, d, h);
  h.dims = d.dims;
  h.datatypeName = dt.name;
  h.sclInter = d.offset;
  h.sclSlope = d.scale;
  h.intentName = "layout " + d.layoutText;
  const long long need = dt.bytes == 0 ? (total + 7) / 8 : total * dt.bytes;
  std::vector<std::uint8_t> dataBytes;
  long long dataOffset = 0;
  const std::vector<std::uint8_t>* data =
      mrtrixData(path, d, bytes, gz, withData, need, dataBytes, dataOffset);
  checkDwScheme(path, img, total);
  if (withData) readMrtrixVoxels(d, dt, ranks, data->data() + dataOffset, total, img);
  return img;
}

namespace {

// The stride ranks to write: `stridesIn` (empty: 1, 2, 3, ...) cut to the axes, checked distinct and
// non-zero.
std::vector<int> writeRanks(const std::string& path, const std::vector<long long>& dims,
                            const std::vector<int>& stridesIn) {
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
  return ranks;
}

// The header lines of a Float32LE image up to (not including) "file:".
std::string mrtrixHeaderText(const ScalarVolume& v, const std::vector<long long>& dims,
                             const std::vector<int>& ranks, const std::vector<std::string>& extraHeader) {
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
  return hd.str();
}

} // namespace

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
  const std::vector<int> ranks = writeRanks(path, dims, stridesIn);
  std::string head = mrtrixHeaderText(v, dims, ranks, extraHeader);

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
      step(idx, dims, strides, diskPos);
    }
  }
  static_assert(sizeof(float) == 4);
  std::vector<std::uint8_t> dataBytes(disk.size() * 4);
  std::memcpy(dataBytes.data(), disk.data(), dataBytes.size()); // little-endian host (x86-64, aarch64)
  if (mih) {
    const std::string dataName = fs::path(path).stem().string() + ".dat";
    head += "file: " + dataName + " 0\nEND\n";
    OutputBatch batch; // the header never without its data, nor the data without its header
    writeFileBytes((fs::path(path).parent_path() / dataName).string(), dataBytes, false);
    writeFileBytes(path, std::vector<std::uint8_t>(head.begin(), head.end()), false);
    batch.commit();
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
