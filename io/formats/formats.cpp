// SPDX-License-Identifier: GPL-3.0-or-later
// Format detection and the one dispatch behind readHeader / readScalarVolume / readTensorVolume / the
// writers: every command opens every format through here.
#include "io/formats/formats.h"

#include "io/formats/atomic_file.h"
#include "io/formats/format_detail.h"
#include "io/formats/gzip.h"
#include "io/model/error.h"

#include <cstring>
#include <filesystem>
#include <zlib.h>

namespace fs = std::filesystem;

namespace dtf::io {

namespace detail {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void checkInflatable(const std::string& path, const std::string& what, std::size_t stored, bool gz,
                     unsigned long long need, const std::string& note) {
  const std::string head = path + ": " + what;
  if (!gz && need > stored)
    throw InputError(head + "is truncated: its " + std::to_string(stored) + " bytes cannot hold the " +
                     std::to_string(need) + " bytes the header needs" + note);
  if (gz && need / kMaxDeflateRatio > stored + 1)
    throw InputError(head + "is truncated: its " + std::to_string(stored) + " bytes of gzip data cannot hold the " +
                     std::to_string(need) + " bytes the header needs" + note);
  if (gz && need > kBombFloorBytes && need / kBombRatio > stored)
    throw InputError(head + "would inflate " + std::to_string(stored) + " bytes to the " + std::to_string(need) +
                     " the header declares" + note + " (over " + std::to_string(kBombRatio) +
                     "-fold: a deflate bomb or a corrupt header; refused)");
}

void checkInflatable(const std::string& path, const std::string& what, const std::string& file,
                     unsigned long long need, const std::string& note) {
  std::error_code ec;
  const auto stored = static_cast<std::size_t>(fs::file_size(file, ec));
  refuseSpecialFile(file);
  checkInflatable(path, what, ec ? 0 : stored, startsWithGzipMagic(file), need, note);
}

bool startsWithGzipMagic(const std::string& path) {
  unsigned char magic[2] = {0, 0};
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  const bool two = std::fread(magic, 1, 2, f) == 2;
  std::fclose(f);
  return two && magic[0] == 0x1f && magic[1] == 0x8b;
}

void refuseSpecialFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st))
    throw InputError(path + ": it is not a regular file (a device, pipe or socket)");
}

std::vector<std::uint8_t> readRawFile(const std::string& path, std::size_t limit) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": file does not exist");
  if (fs::is_directory(path, ec)) throw InputError(path + ": is a directory");
  refuseSpecialFile(path);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot open the file");
  const auto size = fs::file_size(path, ec);
  if (!ec && size > limit) {
    std::fclose(f);
    throw InputError(path + ": more than " + std::to_string(limit) + " bytes of data; refusing to read on");
  }
  std::vector<std::uint8_t> out(ec ? 0 : static_cast<std::size_t>(size));
  const std::size_t got = out.empty() ? 0 : std::fread(out.data(), 1, out.size(), f);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed || got != out.size()) throw InputError(path + ": cannot read the file");
  return out;
}

std::vector<std::uint8_t> readFileBytes(const std::string& path, bool* wasGzip, std::size_t limit,
                                        std::size_t expect) {
  // The compressed bytes are read whole and inflated in one call (libdeflate), every gzip member of the file.
  std::vector<std::uint8_t> raw = readRawFile(path, std::max(limit, std::size_t(1) << 20));
  const bool gz = isGzip(raw.data(), raw.size());
  if (wasGzip) *wasGzip = gz;
  if (!gz) {
    if (raw.size() > limit)
      throw InputError(path + ": more than " + std::to_string(limit) + " bytes of data; refusing to read on");
    return raw;
  }
  // Without a declared size, a stream inflating more than kBombRatio-fold beyond kBombFloorBytes is refused
  // as a deflate bomb before it fills the memory.
  if (expect == 0) limit = std::min(limit, std::max(kBombFloorBytes, raw.size() * kBombRatio));
  return inflateGzip(path, raw.data(), raw.size(), expect, limit, "the gzip data");
}

std::vector<std::uint8_t> peekFileBytes(const std::string& path, std::size_t n) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return {};
  gzFile g = gzopen(path.c_str(), "rb");
  if (!g) return {};
  std::vector<std::uint8_t> out(n);
  const int r = gzread(g, out.data(), static_cast<unsigned>(n));
  gzclose(g);
  out.resize(r > 0 ? static_cast<std::size_t>(r) : 0);
  return out;
}

void writeFileBytes(const std::string& path, const std::vector<std::uint8_t>& bytes, bool gz) {
  AtomicOutput out(path);
  bool ok = true;
  std::FILE* f = std::fopen(out.tempPath().c_str(), "wb");
  if (!f) throw InputError("cannot write " + path + ": cannot open the file for writing");
  if (gz) {
    const std::vector<std::uint8_t> packed = gzipCompress(bytes.data(), bytes.size());
    ok = std::fwrite(packed.data(), 1, packed.size(), f) == packed.size();
  } else {
    ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  }
  ok = std::fclose(f) == 0 && ok;
  if (!ok) throw InputError("cannot write " + path + ": write failed (disk full?)");
  out.commit();
}

StoredGradients readStoredGradients(const std::string& path, const FormatGuess& g) {
  if (g.format == FileFormat::DsiStudioSrc) return readDsiSrc(path);
  if (g.format != FileFormat::Mrtrix)
    throw InputError(path + ": no gradient table inside a " + formatName(g.format) +
                     " file; give --bval and --bvec");
  MrtrixImage m = readMrtrix(path, true);
  if (m.dwScheme.empty())
    throw InputError(path + ": the MRtrix image has no dw_scheme entry; give --bval and --bvec");
  if (m.volume.components < 2) throw InputError(path + " is not a 4D diffusion series (it holds one volume)");
  // dw_scheme rows are (gx, gy, gz, b) in the scanner frame.
  StoredGradients out;
  for (const auto& row : m.dwScheme) {
    out.bvals.push_back(row[3]);
    out.directions.push_back(glm::dvec3(row[0], row[1], row[2]));
  }
  out.signal = std::move(m.volume);
  out.table = "dw_scheme";
  return out;
}

} // namespace detail

using namespace detail;

const char* formatName(FileFormat f) {
  switch (f) {
  case FileFormat::Nifti:
    return "NIfTI";
  case FileFormat::Mrtrix:
    return "MRtrix image";
  case FileFormat::Nrrd:
    return "NRRD";
  case FileFormat::DtifitSet:
    return "FSL dtifit set";
  case FileFormat::DsiStudioSrc:
    return "DSI Studio SRC";
  case FileFormat::DsiStudioFib:
    return "DSI Studio FIB";
  case FileFormat::Afni:
    return "AFNI dataset";
  }
  return "unknown";
}

namespace {

bool startsWith(const std::vector<std::uint8_t>& b, const char* magic) {
  const std::size_t n = std::strlen(magic);
  return b.size() >= n && std::memcmp(b.data(), magic, n) == 0;
}

// A MATLAB v4 header at the start: type 0..5 numeric in P, little-endian, small name length.
bool looksLikeMatlab4(const std::vector<std::uint8_t>& b) {
  if (b.size() < 20) return false;
  std::int32_t h[5];
  std::memcpy(h, b.data(), sizeof h);
  return h[0] >= 0 && h[0] < 100 && h[0] % 10 == 0 && h[1] > 0 && h[2] > 0 && (h[3] == 0 || h[3] == 1) &&
         h[4] > 1 && h[4] < 64;
}

} // namespace

FormatGuess detectFormat(const std::string& path) {
  FormatGuess g;
  std::error_code ec;
  const bool exists = fs::is_regular_file(path, ec);
  const bool dsiName = endsWith(path, ".src.gz") || endsWith(path, ".src") || endsWith(path, ".fib.gz") ||
                       endsWith(path, ".fib");
  if (exists) {
    const std::vector<std::uint8_t> head = peekFileBytes(path, 540);
    if (startsWith(head, "mrtrix image")) {
      g.format = FileFormat::Mrtrix;
      g.reason = "content starts with 'mrtrix image'";
      return g;
    }
    if (startsWith(head, "NRRD000")) {
      g.format = FileFormat::Nrrd;
      g.reason = "content starts with the NRRD magic '" + std::string(head.begin(), head.begin() + 8) + "'";
      return g;
    }
    if (head.size() >= 4) {
      std::int32_t s;
      std::memcpy(&s, head.data(), 4);
      const auto sw = static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(s)));
      if (s == 348 || s == 540 || sw == 348 || sw == 540) {
        g.format = FileFormat::Nifti;
        g.reason =
            "content starts with NIfTI sizeof_hdr " + std::to_string(s == 348 || sw == 348 ? 348 : 540);
        return g;
      }
    }
    if (looksLikeMatlab4(head) || dsiName) {
      const bool fib = endsWith(path, ".fib.gz") || endsWith(path, ".fib");
      g.format = fib ? FileFormat::DsiStudioFib : FileFormat::DsiStudioSrc;
      g.reason = std::string(looksLikeMatlab4(head) ? "MATLAB v4 matrices" : "content not recognised") +
                 ", name ends in " +
                 (fib       ? ".fib[.gz]"
                  : dsiName ? ".src[.gz]"
                            : "something else") +
                 " => DSI Studio " + (fib ? "FIB" : "SRC");
      return g;
    }
  } else if (const std::string base = dtifitBasename(path); !base.empty()) {
    g.format = FileFormat::DtifitSet;
    g.reason = "no such file, but dtifit outputs " + base + "_V1/_L1... exist";
    return g;
  }
  // By name (the file is missing or its content was not recognised; the reader then says what is wrong).
  if (endsWith(path, ".HEAD")) {
    g.format = FileFormat::Afni;
    g.reason = "name ends in .HEAD (AFNI dataset header)";
  } else if (endsWith(path, ".mif") || endsWith(path, ".mif.gz") || endsWith(path, ".mih")) {
    g.format = FileFormat::Mrtrix;
    g.reason = "name ends in .mif/.mif.gz/.mih";
  } else if (endsWith(path, ".nrrd") || endsWith(path, ".nhdr")) {
    g.format = FileFormat::Nrrd;
    g.reason = "name ends in .nrrd/.nhdr";
  } else if (dsiName) {
    g.format = endsWith(path, ".fib.gz") || endsWith(path, ".fib") ? FileFormat::DsiStudioFib
                                                                   : FileFormat::DsiStudioSrc;
    g.reason = "name ends in a DSI Studio extension";
  } else {
    g.format = FileFormat::Nifti;
    g.reason = "not recognised by content; read as NIfTI";
  }
  return g;
}

bool hasEmbeddedGradients(const std::string& path) {
  return hasEmbeddedGradients(path, detectFormat(path));
}

bool hasEmbeddedGradients(const std::string& path, const FormatGuess& g) {
  try {
    if (g.format == FileFormat::DsiStudioSrc) return true;
    if (g.format == FileFormat::Mrtrix) return !readMrtrix(path, false).dwScheme.empty();
  } catch (const Error&) {
  }
  return false;
}

std::string dtifitSetOf(const std::string& path) {
  try {
    return dtifitBasename(path);
  } catch (const Error&) {
    return {};
  }
}

bool isDtifitTensorSet(const std::string& path) {
  const std::string base = dtifitSetOf(path);
  if (base.empty()) return false;
  for (const char* m : {"V1", "V2", "V3", "L1", "L2", "L3"})
    if (dtifitMemberFile(base, m).empty()) return false;
  return true;
}

bool isWritableVolumeName(const std::string& path) {
  for (const char* e : {".nii", ".nii.gz", ".mif", ".mif.gz", ".mih"})
    if (endsWith(path, e) && path.size() > std::strlen(e)) return true;
  return false;
}

bool isWritableTensorName(const std::string& path) {
  return isWritableVolumeName(path) || (endsWith(path, ".nrrd") && path.size() > 5);
}

namespace {

bool isMrtrixName(const std::string& path) {
  return endsWith(path, ".mif") || endsWith(path, ".mif.gz") || endsWith(path, ".mih");
}

void noteFormat(VolumeHeader& h, const FormatGuess& g) {
  h.format = formatName(g.format);
  h.formatReason = g.reason;
}

[[noreturn]] void notAVolume(const std::string& path, const FormatGuess& g) {
  throw InputError(
      path + ": a " + formatName(g.format) +
      " file holds fibre populations, not one volume: `dtfabric render` and `info` read it as a fibre set (" +
      g.reason + ")");
}

} // namespace

VolumeHeader readHeader(const std::string& path) {
  return readHeader(path, detectFormat(path));
}

VolumeHeader readHeader(const std::string& path, const FormatGuess& g) {
  VolumeHeader h;
  switch (g.format) {
  case FileFormat::Nifti:
    h = readNiftiHeader(path);
    break;
  case FileFormat::Mrtrix:
    h = readMrtrix(path, false).header;
    break;
  case FileFormat::Nrrd:
    h = readNrrd(path, false).header;
    break;
  case FileFormat::DtifitSet:
    h = dtifitHeader(path);
    break;
  case FileFormat::DsiStudioSrc:
    h = dsiHeader(path);
    break;
  case FileFormat::DsiStudioFib:
    notAVolume(path, g);
  case FileFormat::Afni:
    readAfni(path, &h, false);
    break;
  }
  noteFormat(h, g);
  return h;
}

ScalarVolume readScalarVolume(const std::string& path, VolumeHeader* header) {
  return readScalarVolume(path, detectFormat(path), header);
}

ScalarVolume readScalarVolume(const std::string& path, const FormatGuess& g, VolumeHeader* header) {
  ScalarVolume v;
  VolumeHeader h;
  switch (g.format) {
  case FileFormat::Nifti:
    v = readNiftiScalarVolume(path, &h);
    break;
  case FileFormat::Mrtrix: {
    MrtrixImage m = readMrtrix(path, true);
    v = std::move(m.volume);
    h = std::move(m.header);
    break;
  }
  case FileFormat::Nrrd: {
    NrrdVolume n = readNrrd(path, true);
    v = std::move(n.volume);
    h = std::move(n.header);
    break;
  }
  case FileFormat::DtifitSet:
    throw InputError(path + ": an FSL dtifit set is read as tensors, not as one volume (" + g.reason + ")");
  case FileFormat::DsiStudioSrc:
    v = readDsiSrcSignal(path, &h);
    break;
  case FileFormat::DsiStudioFib:
    notAVolume(path, g);
  case FileFormat::Afni:
    v = readAfni(path, &h, true);
    break;
  }
  noteFormat(h, g);
  if (header) *header = std::move(h);
  return v;
}

LoadedTensors readTensorVolume(const std::string& path, TensorLayout layout) {
  return readTensorVolume(path, detectFormat(path), layout);
}

LoadedTensors readTensorVolume(const std::string& path, const FormatGuess& format, TensorLayout layout) {
  FormatGuess g = format;
  // A dtifit member (dti_V1, dti_L2, dti_FA ...) that is not itself a tensor volume stands for its set,
  // unless a layout is given: then the file itself is meant.
  if (g.format == FileFormat::Nifti && layout == TensorLayout::Auto && !dtifitBasename(path).empty()) {
    const VolumeHeader h = readNiftiHeader(path);
    if (!(h.dims.size() >= 4 && h.dims[3] == 6)) {
      g.format = FileFormat::DtifitSet;
      g.reason = "NIfTI file named as a member of the dtifit set " + dtifitBasename(path);
    }
  }
  LoadedTensors t;
  switch (g.format) {
  case FileFormat::Nifti:
    t = readNiftiTensorVolume(path, layout);
    break;
  case FileFormat::Mrtrix: {
    MrtrixImage m = readMrtrix(path, true);
    t.header = std::move(m.header);
    if (m.volume.components != 6)
      throw InputError(path + ": is not a tensor image: dimensions " + [&] {
        std::string s;
        for (std::size_t i = 0; i < t.header.dims.size(); ++i)
          s += (i ? "x" : "") + std::to_string(t.header.dims[i]);
        return s;
      }() + " (expected 4D with 6 volumes)");
    tensorsFromComponents(t, m.volume, layout, false, path, TensorLayout::Mrtrix);
    if (layout == TensorLayout::Auto) t.layoutReason = "MRtrix image; " + t.layoutReason;
    break;
  }
  case FileFormat::Nrrd:
    t = nrrdTensors(path);
    break;
  case FileFormat::DtifitSet:
    t = readDtifit(path);
    break;
  case FileFormat::DsiStudioSrc:
    throw InputError(path + ": a DSI Studio SRC file is a DWI; fit it (dtfabric fit) or open it as INPUT of "
                            "render/surface/view, which fit it");
  case FileFormat::DsiStudioFib:
    notAVolume(path, g);
  case FileFormat::Afni:
    throw InputError(path + ": AFNI tensor datasets are not read yet (" + g.reason +
                     "); an eigenvector dataset such as 3dDWItoDT's V1 gives no tensor");
  }
  noteFormat(t.header, g);
  return t;
}

void writeTensorVolume(const std::string& path, const TensorField& field, TensorLayout layout,
                       int niftiVersion) {
  if (endsWith(path, ".nrrd")) {
    writeNrrdTensors(path, field);
    return;
  }
  if (!isMrtrixName(path)) {
    writeNiftiTensorVolume(path, field, layout, niftiVersion);
    return;
  }
  // MRtrix's convention: xx yy zz xy xz yz, world (scanner) frame.
  const std::size_t nv = field.grid.voxelCount();
  if (field.tensors.size() != nv || field.valid.size() != nv)
    throw InputError("cannot write " + path + ": tensor field size does not match its grid");
  ScalarVolume v(field.grid, 6);
  for (std::size_t i = 0; i < nv; ++i) {
    if (!field.valid[i]) continue;
    const SymTensor& t = field.tensors[i];
    const glm::dmat3 m = t.toMat();
    const double mr[6] = {m[0][0], m[1][1], m[2][2], m[0][1], m[0][2], m[1][2]};
    for (int k = 0; k < 6; ++k)
      v.data[i * 6 + static_cast<std::size_t>(k)] = static_cast<float>(mr[k]);
  }
  writeMrtrix(path, v, {},
              {"comments: dtfabric tensor layout=mrtrix units=mm2/s (xx yy zz xy xz yz, world frame)"});
}

void writeScalarVolume(const std::string& path, const ScalarVolume& v, int niftiVersion,
                       const std::string& descrip) {
  if (isMrtrixName(path))
    writeMrtrix(path, v);
  else
    writeNiftiScalarVolume(path, v, niftiVersion, descrip);
}

} // namespace dtf::io
