// SPDX-License-Identifier: GPL-3.0-or-later
// NIfTI-1/NIfTI-2 reading and writing through nifticlib's nifti2 API (which reads both versions, .nii and
// .nii.gz). Everything nifticlib-specific stays in this file; callers see Grid, Volume and TensorField.
#include "io/formats/format_detail.h"
#include "io/formats/gzip.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/model/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <nifti2_io.h>
#include <sstream>
#include <type_traits>

namespace fs = std::filesystem;

namespace dtf::io {

const char* layoutName(TensorLayout l) {
  switch (l) {
  case TensorLayout::Auto:
    return "auto";
  case TensorLayout::Fsl:
    return "fsl";
  case TensorLayout::Mrtrix:
    return "mrtrix";
  case TensorLayout::Symmatrix:
    return "symmatrix";
  case TensorLayout::Dtitk:
    return "dtitk";
  }
  return "unknown";
}

TensorLayout parseLayout(const std::string& name) {
  for (TensorLayout l : {TensorLayout::Auto, TensorLayout::Fsl, TensorLayout::Mrtrix, TensorLayout::Symmatrix,
                         TensorLayout::Dtitk})
    if (name == layoutName(l)) return l;
  throw UsageError("unknown tensor layout '" + name + "' (expected fsl, mrtrix, symmatrix, dtitk or auto)");
}

namespace {

using detail::SampleType;
using detail::SampleTypeInfo;
using detail::sampleTypeInfo;

// More voxels than this (all dimensions multiplied) is refused before anything is allocated.
constexpr long long kMaxElements = 1LL << 31;
// sform/qform disagreement thresholds: translation/scale in mm, rotation as matrix entries.
constexpr double kAffineTolMm = 1e-3;
constexpr double kAffineTolRot = 1e-4;

struct NimDeleter {
  void operator()(nifti_image* nim) const { nifti_image_free(nim); }
};
using NimPtr = std::unique_ptr<nifti_image, NimDeleter>;

using detail::ComponentEvidence;
using detail::componentEvidence;
using detail::ComponentKind;
using detail::fail;
using detail::startsWithGzipMagic;

void quietNifti() {
  // nifticlib reports problems on stderr at debug level >= 1; our exceptions carry the message instead.
  static std::once_flag once;
  std::call_once(once, [] { nifti_set_debug_level(0); });
}

// NIfTI datatypes onto the sample table; the others (complex, RGB, float128) are refused.
const SampleTypeInfo* sampleTypeOf(int dt) {
  static const struct {
    int code;
    SampleType type;
  } kTypes[] = {{DT_UINT8, SampleType::UInt8},     {DT_INT8, SampleType::Int8},
                {DT_INT16, SampleType::Int16},     {DT_UINT16, SampleType::UInt16},
                {DT_INT32, SampleType::Int32},     {DT_UINT32, SampleType::UInt32},
                {DT_INT64, SampleType::Int64},     {DT_UINT64, SampleType::UInt64},
                {DT_FLOAT32, SampleType::Float32}, {DT_FLOAT64, SampleType::Float64}};
  for (const auto& k : kTypes)
    if (k.code == dt) return &sampleTypeInfo(k.type);
  return nullptr;
}

bool isSupportedDatatype(int dt) {
  return sampleTypeOf(dt) != nullptr;
}

std::string intentText(int code) {
  // nifticlib's nifti_intent_string() does not know the vector intents used by FSL and DTI tools.
  switch (code) {
  case NIFTI_INTENT_SYMMATRIX:
    return "SYMMATRIX";
  case NIFTI_INTENT_VECTOR:
    return "VECTOR";
  case NIFTI_INTENT_DISPVECT:
    return "DISPVECT";
  case 2003:
    return "RGB_VECTOR";
  case 2004:
    return "RGBA_VECTOR";
  default:
    break;
  }
  const char* s = nifti_intent_string(code);
  return s ? s : "code " + std::to_string(code);
}

glm::dmat4 toGlm(const nifti_dmat44& m) {
  glm::dmat4 g(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      g[c][r] = m.m[r][c];
  return g;
}

nifti_dmat44 fromGlm(const glm::dmat4& g) {
  nifti_dmat44 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      m.m[r][c] = g[c][r];
  return m;
}

// Largest difference between two affines' 3x3 blocks after normalising columns (rotation), and between
// their columns' lengths and translations (mm).
void affineDifference(const glm::dmat4& a, const glm::dmat4& b, double& mm, double& rot) {
  mm = rot = 0;
  for (int c = 0; c < 3; ++c) {
    glm::dvec3 ca(a[c]), cb(b[c]);
    double la = glm::length(ca), lb = glm::length(cb);
    mm = std::max(mm, std::abs(la - lb));
    if (la > 0 && lb > 0) {
      glm::dvec3 d = ca / la - cb / lb;
      rot = std::max({rot, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    }
  }
  glm::dvec3 t = glm::dvec3(a[3]) - glm::dvec3(b[3]);
  mm = std::max({mm, std::abs(t.x), std::abs(t.y), std::abs(t.z)});
}

std::string dimsText(const std::vector<long long>& dims) {
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i)
    s += (i ? "x" : "") + std::to_string(dims[i]);
  return s;
}

// Checks dims[1..ndim] (each >= 1, all together at most 2^31 values) and appends them to `out`.
void checkedDims(const std::string& path, const long long* dims, long long ndim,
                 std::vector<long long>& out) {
  long long total = 1;
  for (long long d = 1; d <= ndim; ++d) {
    const long long n = dims[d];
    out.push_back(n);
    if (n <= 0) fail(path, "dimension " + std::to_string(d) + " is " + std::to_string(n) + " (must be >= 1)");
    if (n > kMaxElements || total > kMaxElements / n)
      fail(path, "dimensions " + dimsText(out) + (d < ndim ? "..." : "") +
                     " are absurd (more than 2^31 values); refusing to allocate");
    total *= n;
  }
}

// The file holding the voxel data: the file named for single-file .nii/.nii.gz (data offset >= 352),
// nifticlib's image name for a .hdr/.img pair.
std::string dataFile(const nifti_image* nim, const std::string& path) {
  return (nim->iname_offset == 0 && nim->iname) ? std::string(nim->iname) : path;
}

// Whether the voxel data are gzip-compressed, told from the content: a .nii.gz holding plain bytes reads as
// plain. A separate .img of exactly the raw data's size is plain whatever its first bytes are (voxel values
// can begin 1f 8b).
bool dataIsGzip(const nifti_image* nim, const std::string& file, long long rawBytes) {
  if (!startsWithGzipMagic(file)) return false;
  if (nim->iname_offset != 0) return true; // a single file starts with its header, never 1f 8b
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  return ec || static_cast<long long>(size) != rawBytes;
}

// nifticlib decompresses by the name: gzip data under a name without .gz would be read as raw bytes.
void refuseGzipWithoutGzName(const std::string& path, const std::string& file) {
  if (nifti_is_gzfile(file.c_str())) return;
  fail(path, (file == path ? std::string("the file") : "its data file " + file) +
                 " is gzip-compressed but its name does not end in .gz: rename it to " + file + ".gz");
}

// Reads the start of the file before nifticlib does: for a file shorter than the header its sizeof_hdr
// announces, nifti_read_header prints "** ERROR ... short header read" on stderr whatever its debug level.
void checkHeaderLength(const std::string& path) {
  const std::string unreadable = "not a readable NIfTI-1/NIfTI-2 file";
  detail::refuseSpecialFile(path);
  const bool gz = startsWithGzipMagic(path);
  if (gz) refuseGzipWithoutGzName(path, path);
  znzFile fp = znzopen(path.c_str(), "rb", gz);
  if (znz_isnull(fp)) fail(path, "cannot open the file");
  unsigned char head[540];
  std::size_t got = 0, r = 0;
  while (got < sizeof head && (r = znzread(head + got, 1, sizeof head - got, fp)) > 0 &&
         r != static_cast<std::size_t>(-1))
    got += r;
  znzclose(fp);
  if (r == static_cast<std::size_t>(-1)) fail(path, unreadable + " (corrupt gzip stream in the header)");
  if (got < 4) fail(path, unreadable + " (" + std::to_string(got) + " bytes: no header)");
  std::uint32_t raw;
  std::memcpy(&raw, head, sizeof raw);
  const auto sizeofHdr = static_cast<std::int32_t>(raw);
  const auto swapped = static_cast<std::int32_t>(__builtin_bswap32(raw));
  const std::size_t need = sizeofHdr == 540 || swapped == 540   ? 540
                           : sizeofHdr == 348 || swapped == 348 ? 348
                                                                : 0;
  if (need == 0)
    fail(path, "bad sizeof_hdr " + std::to_string(sizeofHdr) + " (NIfTI-1 has 348, NIfTI-2 540)");
  if (got < need)
    fail(path, unreadable + " (the NIfTI-" + (need == 540 ? "2" : "1") + " header is truncated: " +
                   std::to_string(got) + " of " + std::to_string(need) + " bytes)");
}

// The fields of the raw header that nifticlib would convert silently, in the host's byte order.
struct RawNiftiHeader {
  int version = 1;
  long long dims[8] = {};
  int datatype = 0;
  double voxOffset = 0;
  int sizeofHdr = 0;
  bool sizeOk = false, isNifti = false, singleFile = false;
};

template <typename H, typename DimInt> void rawFields(const H* h, bool swap, RawNiftiHeader& r) {
  for (int d = 0; d < 8; ++d) {
    auto v = static_cast<std::make_unsigned_t<DimInt>>(h->dim[d]);
    if (swap)
      v = sizeof(DimInt) == 8 ? static_cast<decltype(v)>(__builtin_bswap64(v))
                              : static_cast<decltype(v)>(__builtin_bswap16(static_cast<std::uint16_t>(v)));
    r.dims[d] = static_cast<DimInt>(v);
  }
  const auto dt = static_cast<std::uint16_t>(h->datatype);
  r.datatype = static_cast<std::int16_t>(swap ? __builtin_bswap16(dt) : dt);
}

// Reads the raw header before nifticlib converts it: nifticlib reads ANALYZE 7.5 (no magic), turns
// dimensions <= 0 into 1, and can crash converting absurd NIfTI-2 dimensions. nifti_type reads back as
// NIfTI-1 for NIfTI-2 files; the header reader gives the version.
RawNiftiHeader readRawHeader(const std::string& path) {
  RawNiftiHeader r;
  void* raw = nifti_read_header(path.c_str(), &r.version, 0);
  if (!raw)
    fail(path, "not a readable NIfTI-1/NIfTI-2 file (bad or truncated header, or corrupt gzip stream)");
  const bool v2 = r.version == 2;
  const auto* h1 = static_cast<const nifti_1_header*>(raw);
  const auto* h2 = static_cast<const nifti_2_header*>(raw);
  const char* magic = v2 ? h2->magic : h1->magic;
  r.isNifti = v2 ? !std::memcmp(magic, "n+2", 4) || !std::memcmp(magic, "ni2", 4)
                 : !std::memcmp(magic, "n+1", 4) || !std::memcmp(magic, "ni1", 4);
  r.singleFile = !std::memcmp(magic, "n+", 2);
  // A header that still reads in the other byte order (sizeof_hdr not 348/540) is swapped here.
  r.sizeofHdr = v2 ? h2->sizeof_hdr : h1->sizeof_hdr;
  const int expectHdr = v2 ? 540 : 348;
  const auto swappedHdr = static_cast<int>(__builtin_bswap32(static_cast<std::uint32_t>(r.sizeofHdr)));
  r.sizeOk = r.sizeofHdr == expectHdr || swappedHdr == expectHdr;
  const bool swap = r.sizeofHdr != expectHdr;
  if (v2) {
    rawFields<nifti_2_header, std::int64_t>(h2, swap, r);
    const auto off = static_cast<std::uint64_t>(h2->vox_offset);
    r.voxOffset = static_cast<double>(static_cast<std::int64_t>(swap ? __builtin_bswap64(off) : off));
  } else {
    rawFields<nifti_1_header, std::int16_t>(h1, swap, r);
    std::uint32_t off;
    std::memcpy(&off, &h1->vox_offset, sizeof off);
    if (swap) off = __builtin_bswap32(off);
    float voxOffset;
    std::memcpy(&voxOffset, &off, sizeof voxOffset);
    r.voxOffset = voxOffset;
  }
  std::free(raw);
  return r;
}

std::string datatypeText(int code) {
  const char* name = nifti_datatype_to_string(code);
  std::string text = name && std::strcmp(name, "DT_UNKNOWN") ? name : "code " + std::to_string(code);
  if (text.rfind("NIFTI_TYPE_", 0) == 0) text.erase(0, 11); // "FLOAT32", "INT16", ...
  return text;
}

// Refuses what nifticlib would read wrongly or not at all: no magic, a vox_offset it cannot use (it would
// replace it with the header size and read the wrong bytes silently), odd dimension counts, datatypes
// the converter table lacks, dimensions <= 0 or absurd. Returns the number of dimensions.
long long checkRawHeader(const std::string& path, const RawNiftiHeader& r) {
  if (!r.sizeOk)
    fail(path, "bad sizeof_hdr " + std::to_string(r.sizeofHdr) + " (NIfTI-1 has 348, NIfTI-2 540)");
  if (!r.isNifti)
    fail(path, "not a NIfTI file: no 'n+1', 'ni1', 'n+2' or 'ni2' magic (ANALYZE 7.5 is not supported)");
  const double minOffset = r.singleFile ? (r.version == 2 ? 540 : 348) + 4 : 0;
  std::ostringstream m;
  m << "vox_offset " << r.voxOffset;
  if (!std::isfinite(r.voxOffset) || r.voxOffset > (r.version == 2 ? 0x1p62 : 0x1p31 - 1))
    fail(path, m.str() + " is absurd");
  if (r.voxOffset < 0) fail(path, m.str() + " is negative");
  if (r.voxOffset < minOffset)
    fail(path, m.str() + " lies inside the header (a single-file NIfTI-" + std::to_string(r.version) +
                   "'s data start at byte " + std::to_string(static_cast<int>(minOffset)) + " or later)");
  const long long ndim = r.dims[0];
  if (ndim < 1 || ndim > 7)
    fail(path, "header has " + std::to_string(ndim) + " dimensions (NIfTI allows 1 to 7)");
  if (!isSupportedDatatype(r.datatype))
    fail(path, "unsupported datatype " + datatypeText(r.datatype) +
                   " (supported: integer types, FLOAT32 and FLOAT64; complex and RGB are not)");
  std::vector<long long> dims;
  checkedDims(path, r.dims, ndim, dims);
  return ndim;
}

// The voxel -> world affine: the sform when its code is set, else the qform, else pixdim only; warnings
// for sform/qform disagreement and pixdim fallbacks. Sets grid and affineSource.
void niftiGrid(const std::string& path, const nifti_image* nim, long long ndim, VolumeHeader& h) {
  glm::ivec3 gdims(1);
  for (int d = 0; d < 3 && d < ndim; ++d)
    gdims[d] = static_cast<int>(h.dims[static_cast<std::size_t>(d)]);
  glm::dmat4 affine(1.0);
  if (nim->sform_code > 0) {
    affine = toGlm(nim->sto_xyz);
    h.affineSource = "sform";
  } else if (nim->qform_code > 0) {
    affine = toGlm(nim->qto_xyz);
    h.affineSource = "qform";
  } else {
    for (int d = 0; d < 3; ++d)
      affine[d][d] = nim->pixdim[d + 1] > 0 ? nim->pixdim[d + 1] : 1.0;
    h.affineSource = "none (pixdim only)";
    h.warnings.emplace_back("neither sform nor qform is set: orientation unknown, assuming RAS voxel axes");
  }
  if (nim->sform_code > 0 && nim->qform_code > 0) {
    double mm, rot;
    affineDifference(toGlm(nim->sto_xyz), toGlm(nim->qto_xyz), mm, rot);
    if (mm > kAffineTolMm || rot > kAffineTolRot) {
      std::ostringstream w;
      w << "sform and qform disagree (by " << mm << " mm, " << rot << " in rotation); using the sform";
      h.warnings.push_back(w.str());
    }
  }
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(affine[c][r]))
        fail(path, "the voxel-to-world affine (" + h.affineSource + ") is not finite");
  if (std::abs(glm::determinant(glm::dmat3(affine))) < 1e-12)
    fail(path, "the voxel-to-world affine is singular");
  // Without an sform the voxel size comes from pixdim, where nifticlib and the pixdim-only affine use 1 mm
  // in place of a value that is not positive: say so rather than show a silently changed size.
  for (int d = 0; d < 3 && d < ndim && nim->sform_code <= 0; ++d)
    if (!(nim->pixdim[d + 1] > 0)) {
      std::ostringstream w;
      w << "pixdim[" << d + 1 << "] is " << nim->pixdim[d + 1]
        << " (a voxel size must be positive); using 1 mm";
      h.warnings.push_back(w.str());
    }
  h.grid = Grid::fromAffine(gdims, affine);
}

// The header facts of nifticlib's reading (checked against the raw header) into `h`.
void niftiHeaderFacts(const std::string& path, const nifti_image* nim, const RawNiftiHeader& r,
                      long long ndim, VolumeHeader& h) {
  h = VolumeHeader{};
  h.path = path;
  h.niftiVersion = r.version == 2 ? 2 : 1;
  if (nim->dim[0] != ndim)
    fail(path, "inconsistent header: nifticlib reads " + std::to_string(nim->dim[0]) + " dimensions");
  if (nim->iname_offset != static_cast<long long>(r.voxOffset))
    fail(path, "inconsistent header: vox_offset " + std::to_string(static_cast<long long>(r.voxOffset)) +
                   " but nifticlib would read the data at byte " + std::to_string(nim->iname_offset));
  long long nimDims[8] = {};
  for (long long d = 0; d <= ndim; ++d)
    nimDims[d] = nim->dim[d];
  checkedDims(path, nimDims, ndim, h.dims);
  h.datatype = nim->datatype;
  const char* dtName = nifti_datatype_to_string(nim->datatype);
  h.datatypeName = dtName ? dtName : ("code " + std::to_string(nim->datatype));
  if (h.datatypeName.rfind("NIFTI_TYPE_", 0) == 0) h.datatypeName.erase(0, 11); // "FLOAT32", "INT16", ...
  if (!isSupportedDatatype(nim->datatype))
    fail(path, "unsupported datatype " + h.datatypeName +
                   " (supported: integer types, FLOAT32 and FLOAT64; complex and RGB are not)");
  h.intentCode = nim->intent_code;
  h.intentName = nim->intent_name;
  if (h.intentName.empty() && nim->intent_code != 0) h.intentName = intentText(nim->intent_code);
  h.descrip = std::string(nim->descrip, strnlen(nim->descrip, sizeof(nim->descrip)));
  h.sclSlope = nim->scl_slope;
  h.sclInter = nim->scl_inter;
  h.qformCode = nim->qform_code;
  h.sformCode = nim->sform_code;
}

// Reads and checks the header only: dimensions sane and not absurd, datatype convertible, file long
// enough (uncompressed files). Fills `h`. Throws InputError naming the file.
NimPtr openHeader(const std::string& path, VolumeHeader& h) {
  quietNifti();
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "file does not exist");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not a NIfTI file");
  checkHeaderLength(path);
  const RawNiftiHeader raw = readRawHeader(path);
  const long long ndim = checkRawHeader(path, raw);
  NimPtr nim(nifti_image_read(path.c_str(), 0));
  if (!nim)
    fail(path, "not a readable NIfTI-1/NIfTI-2 file (bad or truncated header, or corrupt gzip stream)");
  niftiHeaderFacts(path, nim.get(), raw, ndim, h);
  niftiGrid(path, nim.get(), ndim, h);
  long long total = 1;
  for (long long n : h.dims)
    total *= n;
  const std::string file = dataFile(nim.get(), path);
  if (dataIsGzip(nim.get(), file, total * nim->nbyper)) {
    refuseGzipWithoutGzName(path, file);
  } else {
    long long need = static_cast<long long>(nim->iname_offset) + total * nim->nbyper;
    long long have = nifti_get_filesize(file.c_str());
    if (have < need)
      fail(path,
           "file is truncated: " + std::to_string(have) + " bytes, header declares " + std::to_string(need));
  }
  return nim;
}

// Loads the voxel data as float in disk order (i fastest, then j, k, dim4, ...), scaling applied.
// The data are read here rather than by nifti_image_load, which re-resolves the file name and reads
// x.nii when asked for x.nii.gz if both exist.
std::vector<float> loadData(nifti_image* nim, const std::string& path) {
  auto n = static_cast<std::size_t>(nim->nvox);
  std::size_t bytes = n * static_cast<std::size_t>(nim->nbyper);
  const std::string file = dataFile(nim, path);
  const auto offset = static_cast<std::size_t>(nim->iname_offset);
  std::vector<std::uint8_t> inflated;
  std::vector<unsigned char> plain;
  unsigned char* raw = nullptr;
  try {
    if (dataIsGzip(nim, file, static_cast<long long>(bytes))) {
      // The whole gzip file is inflated in one call (libdeflate; every member of a multi-member file), into
      // a buffer the size the header declares and never beyond a little more: a small file whose header
      // declares gigabytes fails on its short data, one that inflates far beyond its header as a bomb.
      const std::size_t declared = offset + bytes;
      const std::vector<std::uint8_t> packed = detail::readRawFile(file);
      const detail::InflateResult r = detail::inflateGzipTo(packed.data(), packed.size(), declared,
                                                            detail::inflateLimit(declared), inflated);
      if (r.status == detail::InflateStatus::TooLarge)
        detail::tooLarge(path, "the voxel data", declared, r.limit);
      if (r.status != detail::InflateStatus::Ok || inflated.size() < declared)
        fail(path, "cannot read the voxel data: the file is truncated or its gzip stream is corrupt (" +
                       (r.status == detail::InflateStatus::Ok
                            ? std::to_string(inflated.size()) + " bytes inflated, the header declares " +
                                  std::to_string(declared)
                            : "gzip member " + std::to_string(r.members + 1) + " at byte " +
                                  std::to_string(r.at) + " does not inflate or fails its CRC-32/size check") +
                       ")");
      raw = inflated.data() + offset;
    } else {
      znzFile fp = znzopen(file.c_str(), "rb", 0);
      if (znz_isnull(fp)) fail(path, "cannot open the file");
      // The file's length was checked against the header, so the buffer is allocated at once.
      bool ok = znzseek(fp, static_cast<znz_off_t>(offset), SEEK_SET) >= 0;
      plain.resize(bytes);
      ok = ok && znzread(plain.data(), 1, bytes, fp) == bytes;
      znzclose(fp);
      if (!ok) fail(path, "cannot read the voxel data: the file is truncated");
      raw = plain.data();
    }
  } catch (const std::bad_alloc&) {
    fail(path, "not enough memory for " + std::to_string(bytes) + " bytes of voxel data");
  }
  if (nim->byteorder != nifti_short_order() && nim->swapsize > 1)
    nifti_swap_Nbytes(static_cast<int64_t>(n), nim->swapsize, raw);
  std::vector<float> out;
  assignAdvised(out, n, 0.0f);
  const SampleTypeInfo* type = sampleTypeOf(nim->datatype);
  if (!type) fail(path, "unsupported datatype"); // openHeader already refused these
  type->toFloat(raw, n, out.data());
  // NIfTI: slope 0 means "no scaling"; a non-finite slope is treated the same way.
  double slope = nim->scl_slope, inter = nim->scl_inter;
  if (slope != 0 && std::isfinite(slope) && std::isfinite(inter) && !(slope == 1 && inter == 0))
    for (float& v : out)
      v = static_cast<float>(v * slope + inter);
  return out;
}

// Disk order (spatial block per component) -> interleaved per voxel.
ScalarVolume interleave(const Grid& grid, int comps, const std::vector<float>& disk) {
  ScalarVolume v(grid, comps);
  std::size_t nv = grid.voxelCount();
  for (int c = 0; c < comps; ++c) {
    const float* src = disk.data() + static_cast<std::size_t>(c) * nv;
    for (std::size_t i = 0; i < nv; ++i)
      v.data[i * comps + c] = src[i];
  }
  return v;
}

// Writes float32 data (disk order) with sform and qform (code 1, scanner) from grid.voxelToWorld.
// dim[0..7] of a float volume on `grid` with up to four extra dimensions.
void writeDims(const Grid& grid, const std::vector<long long>& extraDims, int64_t* dims) {
  const int64_t base[8] = {3, grid.dims.x, grid.dims.y, grid.dims.z, 1, 1, 1, 1};
  std::copy(base, base + 8, dims);
  for (std::size_t e = 0; e < extraDims.size() && e < 4; ++e)
    dims[4 + e] = extraDims[e];
  for (int d = 7; d > 3; --d)
    if (dims[d] > 1) {
      dims[0] = d;
      break;
    }
}

void writeFloatNifti(const std::string& path, const Grid& grid, const std::vector<long long>& extraDims,
                     const std::vector<float>& disk, int intentCode, const char* intentName,
                     const std::string& descrip, int niftiVersion) {
  quietNifti();
  bool gz = path.size() > 7 && path.compare(path.size() - 7, 7, ".nii.gz") == 0;
  bool nii = path.size() > 4 && path.compare(path.size() - 4, 4, ".nii") == 0;
  if (!gz && !nii) throw InputError("cannot write " + path + ": the name must end in .nii or .nii.gz");
  if (niftiVersion != 1 && niftiVersion != 2)
    throw InputError("cannot write " + path + ": NIfTI version must be 1 or 2");
  int64_t dims[8];
  writeDims(grid, extraDims, dims);
  for (int d = 1; d <= 7; ++d)
    if (dims[d] > 32767) niftiVersion = 2; // NIfTI-1 stores dims as int16
  NimPtr nim(nifti_make_new_nim(dims, DT_FLOAT32, 0));
  if (!nim) throw InputError("cannot write " + path + ": nifticlib could not create the header");

  nim->nifti_type = niftiVersion == 2 ? NIFTI_FTYPE_NIFTI2_1 : NIFTI_FTYPE_NIFTI1_1;
  nifti_dmat44 a = fromGlm(grid.voxelToWorld);
  nim->sform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->sto_xyz = a;
  nim->sto_ijk = nifti_dmat44_inverse(a);
  double qfac = 1;
  nifti_dmat44_to_quatern(a, &nim->quatern_b, &nim->quatern_c, &nim->quatern_d, &nim->qoffset_x,
                          &nim->qoffset_y, &nim->qoffset_z, nullptr, nullptr, nullptr, &qfac);
  nim->qfac = qfac;
  nim->qto_xyz = a;
  nim->qto_ijk = nim->sto_ijk;
  nim->dx = nim->pixdim[1] = grid.spacing.x;
  nim->dy = nim->pixdim[2] = grid.spacing.y;
  nim->dz = nim->pixdim[3] = grid.spacing.z;
  nim->pixdim[0] = qfac;
  nim->xyz_units = NIFTI_UNITS_MM;
  nim->intent_code = intentCode;
  if (intentCode == NIFTI_INTENT_SYMMATRIX) nim->intent_p1 = 3; // the standard's N of the N x N matrices
  if (intentName) std::snprintf(nim->intent_name, sizeof(nim->intent_name), "%s", intentName);
  std::snprintf(nim->descrip, sizeof(nim->descrip), "%s", descrip.c_str());
  nim->scl_slope = 1;
  nim->scl_inter = 0;
  // nifticlib builds the header; the bytes are written here, every write checked (nifti_image_write reports
  // a short write only on stderr, and its NIfTI-2 single file gets a zero data offset in nifticlib 2.1).
  std::vector<std::uint8_t> bytes;
  auto put = [&bytes](const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    bytes.insert(bytes.end(), b, b + n);
  };
  const std::size_t dataBytes = disk.size() * sizeof(float);
  // The header of either version: nifticlib converts, the single-file data offset and magic are set here.
  auto header = [&](auto& hdr, auto convert, const char* magic, std::size_t magicBytes, const char* version) {
    if (convert(nim.get(), &hdr) != 0)
      throw InputError("cannot write " + path + ": nifticlib could not build the " + version + " header");
    hdr.vox_offset = sizeof(hdr) + 4;
    std::memcpy(hdr.magic, magic, magicBytes);
    bytes.reserve(sizeof(hdr) + 4 + dataBytes);
    put(&hdr, sizeof(hdr));
  };
  if (niftiVersion == 1) {
    nifti_1_header hdr;
    header(hdr, nifti_convert_nim2n1hdr, "n+1\0", 4, "NIfTI-1");
  } else {
    nifti_2_header hdr;
    header(hdr, nifti_convert_nim2n2hdr, "n+2\0\r\n\032\n", 8, "NIfTI-2");
  }
  const char extender[4] = {0, 0, 0, 0};
  put(extender, 4);
  put(disk.data(), dataBytes);
  detail::writeFileBytes(path, bytes, gz);
}

} // namespace

VolumeHeader detail::readNiftiHeader(const std::string& path) {
  VolumeHeader h;
  openHeader(path, h);
  return h;
}

ScalarVolume detail::readNiftiScalarVolume(const std::string& path, VolumeHeader* header) {
  VolumeHeader h;
  NimPtr nim = openHeader(path, h);
  long long comps = 1;
  for (std::size_t d = 3; d < h.dims.size(); ++d)
    comps *= h.dims[d];
  std::vector<float> disk = loadData(nim.get(), path);
  ScalarVolume v = interleave(h.grid, static_cast<int>(comps), disk);
  if (header) *header = std::move(h);
  return v;
}

void detail::writeNiftiScalarVolume(const std::string& path, const ScalarVolume& v, int niftiVersion,
                                    const std::string& descrip) {
  std::size_t nv = v.grid.voxelCount();
  if (v.components < 1 || v.data.size() != nv * static_cast<std::size_t>(v.components))
    throw InputError("cannot write " + path + ": volume data size does not match its grid");
  std::vector<float> disk(v.data.size());
  for (std::size_t i = 0; i < nv; ++i)
    for (int c = 0; c < v.components; ++c)
      disk[static_cast<std::size_t>(c) * nv + i] = v.data[i * v.components + c];
  std::vector<long long> extra;
  if (v.components > 1) extra.push_back(v.components);
  writeFloatNifti(path, v.grid, extra, disk, 0, nullptr, descrip, niftiVersion);
}

namespace {

// Disk position of each canonical component (xx xy xz yy yz zz) per layout.
constexpr int kFslOrder[6] = {0, 1, 2, 3, 4, 5};       // disk: xx xy xz yy yz zz
constexpr int kMrtrixOrder[6] = {0, 3, 4, 1, 5, 2};    // disk: xx yy zz xy xz yz
constexpr int kSymmatrixOrder[6] = {0, 1, 3, 2, 4, 5}; // disk: xx xy yy xz yz zz (lower triangle, rows)

const int* diskOrder(TensorLayout l) {
  switch (l) {
  case TensorLayout::Mrtrix:
    return kMrtrixOrder;
  case TensorLayout::Symmatrix:
  case TensorLayout::Dtitk:
    return kSymmatrixOrder;
  default:
    return kFslOrder;
  }
}

// Units of the values on disk, in mm^2/s.
double diskUnit(TensorLayout l) {
  return l == TensorLayout::Dtitk ? 1e-3 : 1.0;
}

// Rotation taking the on-disk tensor frame to world RAS. MRtrix stores world tensors. FSL, SYMMATRIX and
// DTI-TK store them in the bvec frame: the voxel axes, with x negated when det(affine) > 0 (FSL's
// convention, which DIPY and DTI-TK follow), so R_frame = R * diag(-1, 1, 1) in that case.
glm::dmat3 frameToWorld(const Grid& g, TensorLayout l) {
  if (l == TensorLayout::Mrtrix) return glm::dmat3(1.0);
  glm::dmat3 r = g.rotation();
  if (glm::determinant(glm::dmat3(g.voxelToWorld)) > 0) r[0] = -r[0];
  return r;
}

constexpr const char* kDescripMarker = "dtfabric tensor layout=";
// A median trace/3 above this (mm^2/s) is far beyond free water at body temperature (3e-3 mm^2/s), so the
// values are taken to be in 1e-3 mm^2/s units.
constexpr double kScaledTraceThreshold = 0.01;

std::string fmt(double v, int precision = 3) {
  std::ostringstream o;
  o.precision(precision);
  o << v;
  return o.str();
}

std::string percent(double fraction) {
  return fmt(100.0 * fraction, 3) + "%";
}

// Median of trace/3 over voxels with finite components and a positive trace (disk units).
double medianTrace(const ScalarVolume& raw, const int* order) {
  std::vector<float> traces;
  std::size_t nv = raw.grid.voxelCount();
  for (std::size_t i = 0; i < nv; ++i) {
    const float* c = &raw.data[i * 6];
    double t = (double(c[order[0]]) + c[order[3]] + c[order[5]]) / 3.0;
    if (std::isfinite(t) && t > 0) traces.push_back(static_cast<float>(t));
  }
  if (traces.empty()) return 0;
  auto mid = traces.begin() + static_cast<std::ptrdiff_t>(traces.size() / 2);
  std::nth_element(traces.begin(), mid, traces.end());
  return *mid;
}

// How well a 4D x 6 volume fits a component order: the fraction of non-zero finite voxels whose
// would-be diagonal is non-negative and whose would-be off-diagonals obey |Dij|^2 <= Dii*Djj (true for
// every positive semi-definite tensor; off-diagonals put on the diagonal break it in most voxels).
struct LayoutFit {
  double plausible = 0;
  double positive[6] = {0, 0, 0, 0, 0, 0}; // fraction of voxels where each disk volume is > 0
  std::size_t voxels = 0;
};

LayoutFit fitOrder(const ScalarVolume& raw, const int* o) {
  LayoutFit f;
  std::size_t plausible = 0, pos[6] = {0, 0, 0, 0, 0, 0};
  std::size_t nv = raw.grid.voxelCount();
  for (std::size_t i = 0; i < nv; ++i) {
    const float* c = &raw.data[i * 6];
    bool finite = true, zero = true;
    for (int k = 0; k < 6; ++k) {
      finite = finite && std::isfinite(c[k]);
      zero = zero && c[k] == 0;
    }
    if (!finite || zero) continue;
    ++f.voxels;
    for (int k = 0; k < 6; ++k)
      pos[k] += c[k] > 0;
    double xx = c[o[0]], xy = c[o[1]], xz = c[o[2]], yy = c[o[3]], yz = c[o[4]], zz = c[o[5]];
    auto fits = [](double off, double a, double b) { return off * off <= a * b * 1.01 + 1e-30; };
    if (xx >= 0 && yy >= 0 && zz >= 0 && fits(xy, xx, yy) && fits(xz, xx, zz) && fits(yz, yy, zz))
      ++plausible;
  }
  if (f.voxels) {
    f.plausible = double(plausible) / double(f.voxels);
    for (int k = 0; k < 6; ++k)
      f.positive[k] = double(pos[k]) / double(f.voxels);
  }
  return f;
}

struct Detection {
  TensorLayout layout = TensorLayout::Fsl;
  bool notTensor = false; // fibre peaks: refused
  bool ambiguous = false; // fits a tensor and peaks: refused, a layout must be named
  std::string reason;
  std::vector<std::string> warnings;
};

Detection detectLayout(const VolumeHeader& h, const ScalarVolume& raw, bool fiveD, TensorLayout preferred) {
  Detection d;
  // Files written by dtfabric name their layout; trust that over heuristics (curvature-tensor phantoms
  // are not diffusion tensors and would fool the scale test).
  if (h.descrip.rfind(kDescripMarker, 0) == 0) {
    std::string name = h.descrip.substr(std::strlen(kDescripMarker));
    name = name.substr(0, name.find(' '));
    for (TensorLayout l :
         {TensorLayout::Fsl, TensorLayout::Mrtrix, TensorLayout::Symmatrix, TensorLayout::Dtitk})
      if (name == layoutName(l)) {
        d.layout = l;
        d.reason = "written by dtfabric: descrip names layout " + name;
        return d;
      }
  }
  if (h.intentCode == NIFTI_INTENT_SYMMATRIX) {
    double m = medianTrace(raw, kSymmatrixOrder);
    std::string base = std::string("intent_code 1005 (SYMMATRIX)") + (fiveD ? ", 5D with dim5 = 6" : "");
    if (m > kScaledTraceThreshold) {
      d.layout = TensorLayout::Dtitk;
      d.reason = base + "; median trace/3 = " + fmt(m) + " looks like 1e-3 mm^2/s units (DTI-TK)";
    } else {
      d.layout = TensorLayout::Symmatrix;
      d.reason = base + "; median trace/3 = " + fmt(m) + " mm^2/s";
    }
    return d;
  }
  LayoutFit fsl = fitOrder(raw, kFslOrder), mrtrix = fitOrder(raw, kMrtrixOrder);
  std::string shape = fiveD ? "6 components (no SYMMATRIX intent)" : "4D with 6 volumes";
  // What the values can be: a tensor is positive semi-definite in nearly every voxel; peaks come in
  // triplets (see componentEvidence). Signs alone are no evidence: sign-normalised peaks have none.
  const ComponentEvidence ev = componentEvidence(raw);
  if (ev.kind == ComponentKind::Peaks) {
    d.notTensor = true;
    d.reason = shape + " that is no tensor but two fibre peaks (" + ev.evidence + ")";
    return d;
  }
  if (ev.kind == ComponentKind::Ambiguous) {
    d.ambiguous = true;
    d.reason = shape + " that fits both a tensor and two fibre peaks (" + ev.evidence + ")";
    return d;
  }
  if (ev.kind == ComponentKind::Neither)
    d.warnings.push_back("the values fit neither a diffusion tensor nor fibre peaks well (" + ev.evidence +
                         "); read as a tensor, use --layout to say what the file holds");
  const std::string assumed = preferred == TensorLayout::Mrtrix ? "MRtrix" : "FSL";
  if (fsl.voxels == 0) {
    d.layout = preferred;
    d.reason = shape + "; no non-zero voxels to tell layouts apart, assuming " + assumed;
    d.warnings.emplace_back("layout guessed (all voxels zero or NaN); use --layout to override");
    return d;
  }
  const LayoutFit& f = fsl; // positive fractions are per disk volume, the same for both hypotheses
  std::string evidence = "volumes 3,5 (FSL yy,zz) positive in " + percent(f.positive[3]) + "/" +
                         percent(f.positive[5]) + ", volumes 1,2 (MRtrix yy,zz) in " +
                         percent(f.positive[1]) + "/" + percent(f.positive[2]) + " of " +
                         std::to_string(f.voxels) + " voxels; positive semi-definite as FSL " +
                         percent(fsl.plausible) + ", as MRtrix " + percent(mrtrix.plausible);
  if (std::abs(fsl.plausible - mrtrix.plausible) < 0.05) {
    d.layout = preferred;
    d.reason = shape + "; ambiguous (" + evidence + "), assuming " + assumed;
    d.warnings.push_back("tensor layout is ambiguous; assumed " + assumed + ", use --layout to override");
  } else {
    d.layout = fsl.plausible > mrtrix.plausible ? TensorLayout::Fsl : TensorLayout::Mrtrix;
    d.reason = shape + "; " + evidence + " => " + layoutName(d.layout);
  }
  double m = medianTrace(raw, diskOrder(d.layout));
  if (m > kScaledTraceThreshold)
    d.warnings.push_back("median trace/3 = " + fmt(m) +
                         " is far above free water's 3e-3 mm^2/s: the values may be in 1e-3 mm^2/s units "
                         "or not diffusion tensors; they are not rescaled");
  return d;
}

// Sylvester's criterion: all leading principal minors positive.
bool positiveDefinite(const glm::dmat3& m) {
  double m1 = m[0][0], m2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  return m1 > 0 && m2 > 0 && glm::determinant(m) > 0;
}

} // namespace

LoadedTensors detail::readNiftiTensorVolume(const std::string& path, TensorLayout layout) {
  LoadedTensors out;
  VolumeHeader& h = out.header;
  NimPtr nim = openHeader(path, h);
  // Shape: 4D x 6 or 5D with dim4 = 1 and dim5 = 6 (trailing dimensions of 1 allowed).
  std::vector<long long> extra(h.dims.begin() + std::min<std::ptrdiff_t>(3, std::ssize(h.dims)),
                               h.dims.end());
  while (!extra.empty() && extra.back() == 1)
    extra.pop_back();
  bool fourD = extra.size() == 1 && extra[0] == 6;
  bool fiveD = extra.size() == 2 && extra[0] == 1 && extra[1] == 6;
  if (!fourD && !fiveD)
    fail(path, "is not a tensor volume: dimensions " + dimsText(h.dims) +
                   " (expected 4D with 6 volumes, or 5D SYMMATRIX with dim5 = 6)");
  std::vector<float> disk = loadData(nim.get(), path);
  nim.reset();
  ScalarVolume raw = interleave(h.grid, 6, disk);
  disk = {};

  tensorsFromComponents(out, raw, layout, fiveD, path, TensorLayout::Fsl);
  return out;
}

void detail::tensorsFromComponents(LoadedTensors& out, const ScalarVolume& raw, TensorLayout layout,
                                   bool fiveD, const std::string& path, TensorLayout preferred) {
  const VolumeHeader& h = out.header;
  out.warnings = h.warnings;
  if (layout == TensorLayout::Auto) {
    Detection d = detectLayout(h, raw, fiveD, preferred);
    if (d.notTensor)
      fail(path, "is not a tensor volume: " + d.reason +
                     " (read it as a fibre set: --layout mrtrix-peaks or dipy-peaks)");
    if (d.ambiguous)
      fail(path,
           "cannot tell what the file holds: " + d.reason +
               "; name it: --layout fsl or mrtrix for a tensor, mrtrix-peaks or dipy-peaks for fibre peaks");
    out.layout = d.layout;
    out.layoutReason = d.reason;
    out.warnings.insert(out.warnings.end(), d.warnings.begin(), d.warnings.end());
  } else {
    out.layout = layout;
    out.layoutReason = std::string("given explicitly (") + layoutName(layout) + ")";
  }

  const int* o = diskOrder(out.layout);
  const double unit = diskUnit(out.layout);
  const glm::dmat3 r = frameToWorld(h.grid, out.layout);
  const bool rotate = out.layout != TensorLayout::Mrtrix;
  out.field = makeTensorField(h.grid);
  std::size_t nv = h.grid.voxelCount();
  for (std::size_t i = 0; i < nv; ++i) {
    const float* c = &raw.data[i * 6];
    bool finite = true, zero = true;
    for (int k = 0; k < 6; ++k) {
      finite = finite && std::isfinite(c[k]);
      zero = zero && c[k] == 0;
    }
    if (!finite) {
      ++out.nanVoxels;
      continue;
    }
    if (zero) continue;
    glm::dmat3 m;
    m[0][0] = c[o[0]];
    m[0][1] = m[1][0] = c[o[1]];
    m[0][2] = m[2][0] = c[o[2]];
    m[1][1] = c[o[3]];
    m[1][2] = m[2][1] = c[o[4]];
    m[2][2] = c[o[5]];
    m *= unit;
    if (rotate) m = r * m * glm::transpose(r);
    out.field.tensors[i] = SymTensor::fromMat(m);
    out.field.valid[i] = 1;
    if (!positiveDefinite(m)) ++out.nonPositiveVoxels;
  }
  if (out.nanVoxels &&
      std::none_of(out.field.valid.begin(), out.field.valid.end(), [](unsigned char v) { return v; }))
    fail(path, "every voxel with data holds NaN/Inf values (" + std::to_string(out.nanVoxels) + " voxels)");
  if (out.nanVoxels)
    out.warnings.push_back(std::to_string(out.nanVoxels) +
                           " voxel(s) hold NaN/Inf components (marked invalid)");
}

void detail::writeNiftiTensorVolume(const std::string& path, const TensorField& field, TensorLayout layout,
                                    int niftiVersion) {
  if (layout == TensorLayout::Auto)
    throw InputError("cannot write " + path + ": choose a tensor layout (fsl, mrtrix, symmatrix or dtitk)");
  std::size_t nv = field.grid.voxelCount();
  if (field.tensors.size() != nv || field.valid.size() != nv)
    throw InputError("cannot write " + path + ": tensor field size does not match its grid");
  const int* o = diskOrder(layout);
  const double unit = diskUnit(layout);
  const glm::dmat3 r = frameToWorld(field.grid, layout);
  const bool rotate = layout != TensorLayout::Mrtrix;
  std::vector<float> disk(nv * 6, 0.0f);
  for (std::size_t i = 0; i < nv; ++i) {
    if (!field.valid[i]) continue;
    glm::dmat3 m = field.tensors[i].toMat();
    if (rotate) m = glm::transpose(r) * m * r;
    m /= unit;
    const double canon[6] = {m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2]};
    for (int k = 0; k < 6; ++k)
      disk[static_cast<std::size_t>(o[k]) * nv + i] = static_cast<float>(canon[k]);
  }
  bool sym = layout == TensorLayout::Symmatrix || layout == TensorLayout::Dtitk;
  std::vector<long long> extra = sym ? std::vector<long long>{1, 6} : std::vector<long long>{6};
  std::string descrip = std::string(kDescripMarker) + layoutName(layout) +
                        (layout == TensorLayout::Dtitk ? " units=1e-3mm2/s" : " units=mm2/s");
  writeFloatNifti(path, field.grid, extra, disk, sym ? NIFTI_INTENT_SYMMATRIX : 0, sym ? "DTI" : nullptr,
                  descrip, niftiVersion);
}

} // namespace dtf::io
