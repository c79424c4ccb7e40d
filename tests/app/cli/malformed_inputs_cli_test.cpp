// SPDX-License-Identifier: GPL-3.0-or-later
// A catalogue of malformed inputs, each generated here from bytes (nothing binary is committed), run
// through the real dtfabric executable: NIfTI volumes (`info`, `fit`), bval/bvec tables (`fit`), .tck/.trk
// tracts (`compare --tracts`, the only command that reads tracts) and viewer scripts (`view --script`,
// which parses the whole script before a window opens, so it runs headless). Every case asserts the exit
// code (2 bad input, 1 usage; never a signal), that stderr names the file and the problem, and, for
// commands with -o, that no output file (not even a temporary one) is left behind.
#include "support/cli.h"
#include "support/test_env.h"
#include "support/zip_builder.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <nifti1.h>
#include <optional>
#include <sys/stat.h>
#include <tuple>
#include <stdexcept>
#include <tuple>
#include <vector>
#include <zlib.h>

namespace fs = std::filesystem;
using dtf::test::CliResult;
using dtf::test::runDtfabric;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T> void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

template <typename T> void poke(std::string& s, std::size_t at, T v) {
  std::memcpy(s.data() + at, &v, sizeof(T));
}

// A single-file NIfTI-1 volume: 348-byte header, 4 zero extension bytes, then `data` verbatim.
struct Nifti {
  std::vector<int> dims{4, 4, 4};
  short datatype = DT_FLOAT32;
  short bitpix = 32;
  float pixdim[3] = {2, 2, 2};
  short qformCode = 0, sformCode = 1;
  float srow[3][4] = {{2, 0, 0, -4}, {0, 2, 0, -4}, {0, 0, 2, -4}};
  float sclSlope = 1;
  std::string data; // empty: float zeros of the right size
  const char* magic = "n+1";

  std::size_t values() const {
    std::size_t n = 1;
    for (int d : dims)
      n *= static_cast<std::size_t>(std::max(d, 0));
    return n;
  }
  std::string bytes() const {
    nifti_1_header h;
    std::memset(&h, 0, sizeof h);
    h.sizeof_hdr = 348;
    h.dim[0] = static_cast<short>(dims.size());
    for (std::size_t i = 0; i < dims.size() && i < 7; ++i)
      h.dim[i + 1] = static_cast<short>(dims[i]);
    h.datatype = datatype;
    h.bitpix = bitpix;
    h.pixdim[0] = 1;
    for (int i = 0; i < 3; ++i)
      h.pixdim[i + 1] = pixdim[i];
    h.vox_offset = 352;
    h.scl_slope = sclSlope;
    h.qform_code = qformCode;
    h.sform_code = sformCode;
    std::memcpy(h.srow_x, srow[0], sizeof h.srow_x);
    std::memcpy(h.srow_y, srow[1], sizeof h.srow_y);
    std::memcpy(h.srow_z, srow[2], sizeof h.srow_z);
    std::memcpy(h.magic, magic, 4); // three letters and the NUL
    std::string s(reinterpret_cast<const char*>(&h), sizeof h);
    s.append(4, '\0');
    s += data.empty() ? std::string(values() * 4, '\0') : data;
    return s;
  }
};

// A NIfTI-2 header (540 bytes, float32, vox_offset 544) with the given dim[0..7], then 64 zero bytes.
std::string nifti2Bytes(const std::vector<std::int64_t>& dims) {
  std::string h(540, '\0');
  poke<std::int32_t>(h, 0, 540);
  std::memcpy(h.data() + 4, "n+2\0\r\n\032\n", 8);
  poke<std::int16_t>(h, 12, DT_FLOAT32);
  poke<std::int16_t>(h, 14, 32);
  for (std::size_t d = 0; d < dims.size() && d < 8; ++d)
    poke<std::int64_t>(h, 16 + 8 * d, dims[d]);
  for (int d = 0; d < 8; ++d)
    poke<double>(h, 104 + 8 * d, 1.0);
  poke<std::int64_t>(h, 168, 544);
  poke<double>(h, 176, 1.0);
  return h + std::string(4 + 64, '\0');
}

std::string floats(const std::vector<float>& v) {
  std::string s;
  for (float f : v)
    put(s, f);
  return s;
}

// A valid FSL-layout tensor volume (2x2x2 x 6, diagonal 1e-3 mm^2/s) with every component set to `fill`
// when given.
Nifti tensorNifti(std::optional<float> fill = std::nullopt) {
  Nifti n;
  n.dims = {2, 2, 2, 6};
  std::vector<float> v(8 * 6, 0.0f);
  for (int c : {0, 3, 5})
    for (int i = 0; i < 8; ++i)
      v[static_cast<std::size_t>(c * 8 + i)] = 1e-3f;
  if (fill) std::fill(v.begin(), v.end(), *fill);
  n.data = floats(v);
  return n;
}

// A valid 4x4x4 DWI with 8 volumes (b=0 first and last) and signal 1000 * exp(-b * 1e-3).
Nifti dwiNifti() {
  Nifti n;
  n.dims = {4, 4, 4, 8};
  std::vector<float> v(64 * 8);
  for (int t = 0; t < 8; ++t)
    for (int i = 0; i < 64; ++i)
      v[static_cast<std::size_t>(t * 64 + i)] = (t == 0 || t == 7) ? 1000.0f : 367.9f + static_cast<float>(t);
  n.data = floats(v);
  return n;
}
const char* kBval = "0 1000 1000 1000 1000 1000 1000 0\n";
const char* kBvec = "0 1 0 0 0.7071 0.7071 0 0\n0 0 1 0 0.7071 0 0.7071 0\n0 0 0 1 0 0.7071 0.7071 0\n";

// A tensor volume of 8x8x8 x 6 pseudo-random floats: its gzip stream is long, so damage to it lands in the
// voxel data rather than in the header.
std::string noisyTensorBytes() {
  Nifti n;
  n.dims = {8, 8, 8, 6};
  std::vector<float> v(512 * 6);
  std::uint32_t x = 12345;
  for (float& f : v) {
    x = x * 1664525u + 1013904223u;
    f = static_cast<float>(x >> 8) * 1e-10f;
  }
  n.data = floats(v);
  return n.bytes();
}

std::string gzip(const std::string& raw) {
  uLongf cap = compressBound(static_cast<uLong>(raw.size())) + 32;
  std::string out(cap, '\0');
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY); // 15 + 16: gzip wrapper
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = static_cast<uInt>(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(cap);
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// A gzip stream of `prefix` followed by `zeros` zero bytes (a deflate bomb when `zeros` is large: about 1 KiB
// of stream per MiB), built in 1 MiB steps.
std::string gzipWithZeros(const std::string& prefix, std::uint64_t zeros) {
  z_stream z{};
  deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY);
  const std::string block(std::size_t(1) << 20, '\0');
  std::string out, buf(std::size_t(1) << 16, '\0');
  auto feed = [&](const char* p, std::size_t n, int flush) {
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(p));
    z.avail_in = static_cast<uInt>(n);
    int rc;
    do {
      z.next_out = reinterpret_cast<Bytef*>(buf.data());
      z.avail_out = static_cast<uInt>(buf.size());
      rc = deflate(&z, flush);
      out.append(buf.data(), buf.size() - z.avail_out);
    } while (z.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
  };
  feed(prefix.data(), prefix.size(), zeros ? Z_NO_FLUSH : Z_FINISH);
  for (std::uint64_t left = zeros; left > 0;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, block.size()));
    left -= n;
    feed(block.data(), n, left ? Z_NO_FLUSH : Z_FINISH);
  }
  deflateEnd(&z);
  return out;
}

// MRtrix .tck: `header` lines between "mrtrix tracks" and "END"; "file: . OFFSET" is added (pointing right
// after END) unless the header names `file:` itself; then `points` as Float32LE triplets.
std::string tck(const std::string& header, const std::vector<float>& points, bool addFile = true) {
  std::string head = "mrtrix tracks\n" + header;
  std::string tail = "END\n";
  if (addFile && header.find("file:") == std::string::npos) {
    std::size_t offset = head.size() + std::strlen("file: . 0000000000\n") + tail.size();
    char line[40];
    std::snprintf(line, sizeof line, "file: . %010zu\n", offset);
    head += line;
  }
  return head + tail + floats(points);
}
const float kNaN = std::numeric_limits<float>::quiet_NaN(), kInf = std::numeric_limits<float>::infinity();
// One streamline of two points, its NaN separator and the end-of-file Inf triplet.
const std::vector<float> kTckPoints = {0, 0, 0, 1, 1, 1, kNaN, kNaN, kNaN, kInf, kInf, kInf};

// TrackVis v2 little-endian header (1000 bytes) on a 4x4x4 grid of 2 mm voxels, LAS, identity-like
// vox_to_ras, followed by one track of two points unless `body` is given.
std::string trk(const std::function<void(std::string&)>& edit = {}, std::optional<std::string> body = {}) {
  std::string h(1000, '\0');
  std::memcpy(h.data(), "TRACK", 5);
  for (int a = 0; a < 3; ++a) {
    poke<std::int16_t>(h, 6 + 2 * a, 4);
    poke<float>(h, 12 + 4 * a, 2.0f);
  }
  for (int r = 0; r < 4; ++r)
    poke<float>(h, 440 + 4 * (4 * r + r), r < 3 ? 2.0f : 1.0f);
  std::memcpy(h.data() + 948, "RAS", 3);
  poke<std::int32_t>(h, 988, 1);
  poke<std::int32_t>(h, 992, 2);
  poke<std::int32_t>(h, 996, 1000);
  if (edit) edit(h);
  if (body) return h + *body;
  std::string b;
  put<std::int32_t>(b, 2);
  b += floats({1, 1, 1, 3, 3, 3});
  return h + b;
}

// A valid TRX zip: 2 streamlines of 2 points (float32 positions, uint32 offsets with the end entry);
// `edit` may change the entries (header.json, positions, offsets) before they are zipped.
std::string trxZip(const std::function<void(std::vector<dtf::test::ZipEntry>&)>& edit = {},
                   bool deflate = false) {
  std::vector<dtf::test::ZipEntry> e = {
      {"header.json",
       R"({"VOXEL_TO_RASMM": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "DIMENSIONS": [8,8,8], )"
       R"("NB_STREAMLINES": 2, "NB_VERTICES": 4})",
       deflate},
      {"positions.3.float32", floats({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3}), deflate},
      {"offsets.uint32", std::string("\0\0\0\0\2\0\0\0\4\0\0\0", 12), deflate}};
  if (edit) edit(e);
  return dtf::test::zipArchive(e);
}

// A 2x2x2 peaks volume with `volumes` volumes (disk order: volume-major), direction-like signed values in
// every volume (sign alternating from voxel to voxel), `set` overriding single values (flat disk index).
Nifti peaksNifti(int volumes, std::vector<std::pair<int, float>> set, std::optional<float> fill = std::nullopt) {
  Nifti n;
  n.dims = {2, 2, 2, volumes};
  std::vector<float> v(static_cast<std::size_t>(8 * volumes));
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = fill ? *fill : ((i % 2) ? -0.5f : 0.7f) * (1.0f + 0.1f * static_cast<float>(i % 5));
  for (auto [i, x] : set)
    v[static_cast<std::size_t>(i)] = x;
  n.data = floats(v);
  return n;
}

const fs::path kSample = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

struct Case {
  std::string name;
  // Writes the inputs into `dir` and returns the dtfabric arguments.
  std::function<std::string(const fs::path& dir)> setup;
  int exitCode = 2;
  std::vector<std::string> errHas; // substrings of stderr
  std::string output;              // file name the command would write (must not exist afterwards)
  std::string outHas;              // for cases that succeed with a warning: a substring of stdout
  // Run under a memory cap (2 GiB of address space; under ASan an RSS limit and no allocation over 1 GiB):
  // for headers that declare gigabytes, the reader must refuse before allocating.
  bool capMemory = false;
};

// The case with the memory cap on.
Case capped(Case c) {
  c.capMemory = true;
  return c;
}

// `info` on a NIfTI file written from `bytes`.
Case infoCase(std::string name, std::string file, std::function<std::string()> bytes,
              std::vector<std::string> errHas, std::string extra = "") {
  return {name,
          [file, bytes, extra](const fs::path& dir) {
            writeBytes(dir / file, bytes());
            return "info " + q(dir / file) + extra;
          },
          2,
          [&] {
            errHas.insert(errHas.begin(), file);
            return errHas;
          }()};
}

// `fit` of a DWI with bval/bvec written from the given texts, output fit.nii.
Case fitCase(std::string name, std::function<std::string()> dwi, std::string bval, std::string bvec,
             std::vector<std::string> errHas) {
  return {name,
          [dwi, bval, bvec](const fs::path& dir) {
            writeBytes(dir / "dwi.nii", dwi());
            writeBytes(dir / "dwi.bval", bval);
            writeBytes(dir / "dwi.bvec", bvec);
            return "fit " + q(dir / "dwi.nii") + " --bval " + q(dir / "dwi.bval") + " --bvec " +
                   q(dir / "dwi.bvec") + " -o " + q(dir / "fit.nii");
          },
          2, errHas, "fit.nii"};
}

// `compare` of a valid constant phantom with a tract file written from `bytes`.
Case tractCase(std::string name, std::string file, std::function<std::string()> bytes,
               std::vector<std::string> errHas) {
  return {name,
          [file, bytes](const fs::path& dir) {
            auto ph = runDtfabric("phantom constant --size 8 -o " + q(dir / "t.nii"), dir);
            if (ph.exitCode != 0) throw std::runtime_error("phantom failed: " + ph.err);
            writeBytes(dir / file, bytes());
            return "compare " + q(dir / "t.nii") + " --tracts " + q(dir / file) + " --surface slice=axial:4";
          },
          2,
          [&] {
            errHas.insert(errHas.begin(), file);
            return errHas;
          }()};
}

// `view --script` of a script file holding `text`.
Case scriptCase(std::string name, std::string text, std::vector<std::string> errHas) {
  return {name,
          [text](const fs::path& dir) {
            writeBytes(dir / "bad.dtfs", text);
            return "view --script " + q(dir / "bad.dtfs");
          },
          2,
          [&] {
            errHas.insert(errHas.begin(), "bad.dtfs:");
            return errHas;
          }()};
}

// `select` of a two-streamline .tck with the region arguments `regions` (the region set file roi.json holds
// `roiText` when given); output out.tck.
Case selectCase(std::string name, std::string regions, std::vector<std::string> errHas, std::string roiText = "",
                int exitCode = 2, std::function<void(const fs::path&)> extra = nullptr) {
  return {name,
          [regions, roiText, extra](const fs::path& dir) {
            if (extra) extra(dir);
            std::string tck = "mrtrix tracks\ndatatype: Float32LE\ncount: 2\nfile: . 64\nEND\n";
            tck.resize(64, ' ');
            auto put = [&](float x, float y, float z) {
              for (float v : {x, y, z})
                tck.append(reinterpret_cast<const char*>(&v), 4);
            };
            const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
            put(0, 0, 0), put(10, 0, 0), put(nan, nan, nan), put(0, 5, 0), put(10, 5, 0), put(nan, nan, nan);
            put(inf, inf, inf);
            writeBytes(dir / "in.tck", tck);
            if (!roiText.empty()) writeBytes(dir / "roi.json", roiText);
            std::string r = regions;
            for (std::string::size_type at; (at = r.find("DIR/")) != std::string::npos;)
              r.replace(at, 4, dir.string() + "/");
            return "select " + q(dir / "in.tck") + " -o " + q(dir / "out.tck") + " " + r;
          },
          exitCode, errHas, "out.tck"};
}

std::vector<Case> catalogue() {
  std::vector<Case> c;
  const std::string notNifti = "not a readable NIfTI";
  // ---- NIfTI headers
  c.push_back(infoCase("NiftiEmptyFile", "empty.nii", [] { return std::string(); }, {notNifti}));
  c.push_back(infoCase("NiftiTruncatedHeader", "short.nii",
                       [] { return tensorNifti().bytes().substr(0, 200); }, {notNifti}));
  // Fuzz finding: a file shorter than the NIfTI-2 header its sizeof_hdr announces made nifticlib print
  // "** ERROR (nifti_read_header): short NIFTI-2 header read" whatever its debug level.
  c.push_back(infoCase("Nifti2TruncatedHeader", "short2.nii",
                       [] {
                         return nifti2Bytes({3, 4, 4, 4}).substr(0, 400);
                       },
                       {notNifti, "the NIfTI-2 header is truncated: 400 of 540 bytes"}));
  c.push_back(infoCase("Nifti2GzipTruncatedHeader", "short2.nii.gz",
                       [] {
                         return gzip(nifti2Bytes({3, 4, 4, 4}).substr(0, 400));
                       },
                       {notNifti, "the NIfTI-2 header is truncated: 400 of 540 bytes"}));
  c.push_back(infoCase("NiftiBadSizeofHdr", "sizeof.nii",
                       [] {
                         auto b = tensorNifti().bytes();
                         poke<std::int32_t>(b, 0, 123);
                         return b;
                       },
                       {"bad sizeof_hdr 123"}));
  c.push_back(infoCase("NiftiWrongMagic", "magic.nii",
                       [] {
                         Nifti n = tensorNifti();
                         n.magic = "XY1";
                         return n.bytes();
                       },
                       {"no 'n+1', 'ni1', 'n+2' or 'ni2' magic"}));
  c.push_back(infoCase("NiftiRandomBytes", "noise.nii",
                       [] {
                         std::string s(1000, '\0');
                         for (std::size_t i = 0; i < s.size(); ++i)
                           s[i] = static_cast<char>((i * 2654435761u) >> 13);
                         return s;
                       },
                       {"NIfTI"}));
  c.push_back(infoCase("NiftiTruncatedData", "cut.nii",
                       [] {
                         auto b = tensorNifti().bytes();
                         return b.substr(0, b.size() - 10);
                       },
                       {"truncated", "bytes"}));
  c.push_back(infoCase("NiftiVoxOffsetPastEnd", "offset.nii",
                       [] {
                         auto b = tensorNifti().bytes();
                         poke<float>(b, 108, 1e6f);
                         return b;
                       },
                       {"truncated"}));
  // nifticlib reads the data from byte 348 when vox_offset is negative, inside the header or beyond int:
  // the wrong bytes (the extension flag first), with no error. Each is refused.
  for (const auto& [name, offset, message] : std::vector<std::tuple<std::string, float, std::string>>{
           {"NiftiVoxOffsetInsideHeader", 10.0f,
            "vox_offset 10 lies inside the header (a single-file NIfTI-1's "
            "data start at byte 352 or later)"},
           {"NiftiVoxOffsetNegative", -5.0f, "vox_offset -5 is negative"},
           {"NiftiVoxOffsetBeyondInt", 1e12f, "vox_offset 1e+12 is absurd"},
           {"NiftiVoxOffsetNaN", std::numeric_limits<float>::quiet_NaN(), "vox_offset nan is absurd"}}) {
    c.push_back(infoCase(name, "voxoffset.nii",
                         [offset = offset] {
                           auto b = tensorNifti().bytes();
                           poke<float>(b, 108, offset);
                           return b;
                         },
                         {message}));
  }
  c.push_back(
      infoCase("Nifti2VoxOffsetInsideHeader", "voxoffset2.nii",
               [] {
                 auto b = nifti2Bytes({3, 4, 4, 1});
                 poke<std::int64_t>(b, 168, 540);
                 return b;
               },
               {"vox_offset 540 lies inside the header (a single-file NIfTI-2's data start at byte 544"}));
  c.push_back(infoCase("NiftiGzipTruncated", "cut.nii.gz",
                       [] {
                         auto z = gzip(noisyTensorBytes());
                         return z.substr(0, z.size() * 2 / 3);
                       },
                       {"truncated or its gzip stream is corrupt"}));
  c.push_back(infoCase("NiftiGzipCorruptDeflateData", "flip.nii.gz",
                       [] {
                         auto z = gzip(noisyTensorBytes());
                         for (std::size_t i = z.size() / 2; i < z.size() / 2 + 8; ++i)
                           z[i] = static_cast<char>(z[i] ^ 0x5a);
                         return z;
                       },
                       {"NIfTI"}));
  c.push_back(infoCase("NiftiGzipBadCrc", "crc.nii.gz",
                       [] {
                         auto z = gzip(noisyTensorBytes());
                         z[z.size() - 8] = static_cast<char>(z[z.size() - 8] ^ 0xff); // CRC32 in the trailer
                         return z;
                       },
                       {"gzip stream"}));
  c.push_back(infoCase("NiftiGzipHeaderOnlyDeclaringGigabytes", "huge.nii.gz",
                       [] {
                         Nifti n;
                         n.dims = {1600, 1200, 1000}; // 1.9e9 floats (7.2 GiB) declared, none present
                         n.data = "x";
                         return gzip(n.bytes());
                       },
                       {"truncated or its gzip stream is corrupt"}));
  // ---- NIfTI dimensions and datatypes
  c.push_back(infoCase("NiftiDimsOverflowSizeT", "overflow.nii",
                       [] {
                         Nifti n;
                         n.dims = {32767, 32767, 32767, 32767, 32767, 32767, 32767};
                         n.data = "x";
                         return n.bytes();
                       },
                       {"absurd", "refusing to allocate"}));
  c.push_back(infoCase("NiftiDimsExceedMemory", "big.nii",
                       [] {
                         Nifti n;
                         n.dims = {30000, 30000, 3000};
                         n.data = "x";
                         return n.bytes();
                       },
                       {"absurd"}));
  // Fuzz finding: nifticlib crashed (stack overflow) converting a NIfTI-2 header with an absurd dim[0].
  c.push_back(infoCase("Nifti2AbsurdDimCount", "ndim.nii",
                       [] {
                         return nifti2Bytes({724235330553511936LL, 4, 4, 4, 1, 1, 1, 1});
                       },
                       {"header has 724235330553511936 dimensions"}));
  c.push_back(infoCase("Nifti2AbsurdDims", "huge2.nii",
                       [] {
                         return nifti2Bytes({3, 1LL << 40, 1LL << 40, 4});
                       },
                       {"absurd", "refusing to allocate"}));
  c.push_back(infoCase("NiftiEightDims", "ndim8.nii",
                       [] {
                         auto b = tensorNifti().bytes();
                         poke<std::int16_t>(b, 40, 8);
                         return b;
                       },
                       {"NIfTI"}));
  c.push_back(infoCase("NiftiZeroDim", "zero.nii",
                       [] {
                         Nifti n;
                         n.dims = {4, 0, 4};
                         return n.bytes();
                       },
                       {"dimension 2 is 0"}));
  c.push_back(infoCase("NiftiNegativeDim", "negative.nii",
                       [] {
                         Nifti n;
                         n.dims = {4, 4, -3};
                         n.data = std::string(64 * 4, '\0');
                         return n.bytes();
                       },
                       {"dimension 3 is -3"}));
  c.push_back(infoCase("NiftiZeroNdim", "ndim0.nii",
                       [] {
                         auto b = tensorNifti().bytes();
                         poke<std::int16_t>(b, 40, 0);
                         return b;
                       },
                       {"NIfTI"}));
  c.push_back(infoCase(
      "NiftiSevenDimsReadAsTensors", "sevend.nii",
      [] {
        Nifti n;
        n.dims = {2, 2, 2, 1, 1, 1, 6};
        return n.bytes();
      },
      {"is not a tensor volume", "2x2x2x1x1x1x6"}, " --layout fsl"));
  c.push_back(infoCase("NiftiComplexDatatype", "complex.nii",
                       [] {
                         Nifti n;
                         n.datatype = DT_COMPLEX64;
                         n.bitpix = 64;
                         n.data = std::string(64 * 8, '\0');
                         return n.bytes();
                       },
                       {"unsupported datatype COMPLEX64"}));
  c.push_back(infoCase("NiftiRgbDatatype", "rgb.nii",
                       [] {
                         Nifti n;
                         n.datatype = DT_RGB24;
                         n.bitpix = 24;
                         n.data = std::string(64 * 3, '\0');
                         return n.bytes();
                       },
                       {"unsupported datatype RGB24"}));
  c.push_back(infoCase("NiftiUnknownDatatypeCode", "dt999.nii",
                       [] {
                         Nifti n;
                         n.datatype = 999;
                         return n.bytes();
                       },
                       {"unsupported datatype code 999"}));
  c.push_back(
      infoCase("NiftiAllNaNTensors", "nan.nii", [] { return tensorNifti(kNaN).bytes(); }, {"NaN/Inf"}));
  c.push_back(
      infoCase("NiftiAllInfTensors", "inf.nii", [] { return tensorNifti(kInf).bytes(); }, {"NaN/Inf"}));
  c.push_back(infoCase("NiftiSingularSform", "singular.nii",
                       [] {
                         Nifti n = tensorNifti();
                         std::memset(n.srow, 0, sizeof n.srow);
                         return n.bytes();
                       },
                       {"affine is singular"}));
  c.push_back(infoCase("NiftiNonFiniteSform", "nansform.nii",
                       [] {
                         Nifti n = tensorNifti();
                         n.srow[1][1] = kNaN;
                         return n.bytes();
                       },
                       {"affine"}));
  // Accepted with a warning: orientation problems do not stop a look at the data, but are reported.
  c.push_back({"NiftiNegativePixdimIsReported",
               [](const fs::path& dir) {
                 Nifti n = tensorNifti();
                 n.sformCode = 0;
                 n.pixdim[1] = -2;
                 writeBytes(dir / "pixdim.nii", n.bytes());
                 return "info " + q(dir / "pixdim.nii");
               },
               0,
               {},
               "",
               "pixdim[2] is -2"});
  c.push_back({"NiftiInconsistentQformSformIsReported",
               [](const fs::path& dir) {
                 Nifti n = tensorNifti();
                 n.qformCode = 1; // quaternion zero, offsets zero: 2 mm voxels at the origin, sform at -4 mm
                 writeBytes(dir / "qs.nii", n.bytes());
                 return "info " + q(dir / "qs.nii");
               },
               0,
               {},
               "",
               "sform and qform disagree"});
  c.push_back({"NiftiMissingFile",
               [](const fs::path& dir) { return "info " + q(dir / "missing.nii"); },
               2,
               {"missing.nii", "does not exist"}});
  c.push_back({"NiftiDirectory",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "folder.nii");
                 return "info " + q(dir / "folder.nii");
               },
               2,
               {"folder.nii", "is a directory"}});
  // ---- DWI and gradient tables through `fit` (nothing may be written)
  auto dwi = [] { return dwiNifti().bytes(); };
  c.push_back(fitCase("FitTruncatedDwi",
                      [] {
                        auto b = dwiNifti().bytes();
                        return b.substr(0, b.size() / 2);
                      },
                      kBval, kBvec, {"dwi.nii", "truncated"}));
  c.push_back(fitCase("FitDwiWithComplexData",
                      [] {
                        Nifti n = dwiNifti();
                        n.datatype = DT_COMPLEX64;
                        n.bitpix = 64;
                        n.data += n.data;
                        return n.bytes();
                      },
                      kBval, kBvec, {"dwi.nii", "unsupported datatype"}));
  c.push_back(fitCase("BvalCountMismatch", dwi, "0 1000 1000 1000 1000 0\n", kBvec,
                      {"dwi.bval", "6 b-values", "8 volumes"}));
  c.push_back(fitCase("BvecCountMismatch", dwi, kBval, "0 1 0 0 0\n0 0 1 0 0\n0 0 0 1 0\n",
                      {"dwi.bvec", "5 directions", "8"}));
  c.push_back(fitCase("BvalNonNumeric", dwi, "0 1000 abc 1000 1000 1000 1000 0\n", kBvec,
                      {"dwi.bval", "line 1", "'abc' is not a number"}));
  c.push_back(fitCase("BvecNonNumeric", dwi, kBval,
                      "0 1 0 0 0.7071 0.7071 0 0\n0 0 1 0 x 0 0.7071 0\n0 0 0 1 0 0.7071 0.7071 0\n",
                      {"dwi.bvec", "line 2", "'x' is not a number"}));
  c.push_back(fitCase("BvalEmptyFile", dwi, "", kBvec, {"dwi.bval", "holds no numbers"}));
  c.push_back(fitCase("BvecEmptyFile", dwi, kBval, "\n\n", {"dwi.bvec", "holds no numbers"}));
  c.push_back(fitCase("BvalNegative", dwi, "0 1000 -1000 1000 1000 1000 1000 0\n", kBvec,
                      {"dwi.bval", "not a finite non-negative number"}));
  c.push_back(fitCase("BvalNaN", dwi, "0 1000 nan 1000 1000 1000 1000 0\n", kBvec,
                      {"dwi.bval", "not a finite non-negative number"}));
  c.push_back(fitCase("BvecZeroVectorAtPositiveB", dwi, kBval,
                      "0 1 0 0 0.7071 0 0 0\n0 0 1 0 0.7071 0 0.7071 0\n0 0 0 1 0 0 0.7071 0\n",
                      {"dwi.bvec", "volume 5 has b = 1000", "zero gradient direction"}));
  c.push_back(fitCase("BvecInfinite", dwi, kBval,
                      "0 1 0 0 0.7071 inf 0 0\n0 0 1 0 0.7071 0 0.7071 0\n0 0 0 1 0 0.7071 0.7071 0\n",
                      {"dwi.bvec", "infinite"}));
  c.push_back(fitCase("BvecRaggedShape", dwi, kBval, "0 1 0 0 0.7071 0.7071 0 0\n0 0 1 0 0.7071 0 0.7071 0\n",
                      {"dwi.bvec", "3 rows of N numbers"}));
  c.push_back(fitCase("FitTooFewVolumes",
                      [] {
                        Nifti n = dwiNifti();
                        n.dims = {4, 4, 4, 3};
                        n.data.resize(64 * 3 * 4);
                        return n.bytes();
                      },
                      "0 1000 1000\n", "0 1 0\n0 0 1\n0 0 0\n", {"volumes"}));
  // ---- outputs: never an input, never an existing file without --force
  c.push_back({"FitOutputIsAnInput",
               [](const fs::path& dir) {
                 writeBytes(dir / "dwi.nii", dwiNifti().bytes());
                 writeBytes(dir / "dwi.bval", kBval);
                 writeBytes(dir / "dwi.bvec", kBvec);
                 return "fit " + q(dir / "dwi.nii") + " --bval " + q(dir / "dwi.bval") + " --bvec " +
                        q(dir / "dwi.bvec") + " --force -o " + q(dir / "dwi.nii");
               },
               2,
               {"dwi.nii"}});
  c.push_back({"PhantomExistingOutputNeedsForce",
               [](const fs::path& dir) {
                 writeBytes(dir / "keep.nii", "precious");
                 return "phantom constant --size 8 -o " + q(dir / "keep.nii");
               },
               2,
               {"keep.nii", "exists", "--force"}});
  // A voxel size whose affine is singular or not finite in float: the file was written, then refused by
  // every reader (ours among them).
  for (const auto& [name, spacing] :
       {std::pair{"PhantomSpacingTooLarge", "1e300"}, {"PhantomSpacingTooSmall", "1e-10"}})
    c.push_back({name,
                 [spacing = std::string(spacing)](const fs::path& dir) {
                   return "phantom constant --size 8 --spacing " + spacing + " -o " + q(dir / "sp.nii");
                 },
                 1,
                 {"--spacing must be [0.001, 100]", spacing},
                 "sp.nii"});
  // ---- .tck
  c.push_back(
      tractCase("TckEmptyFile", "empty.tck", [] { return std::string(); }, {"not an MRtrix .tck file"}));
  c.push_back(tractCase("TckBadMagic", "magic.tck",
                        [] {
                          auto s = tck("datatype: Float32LE\n", kTckPoints);
                          s[0] = 'M';
                          return s;
                        },
                        {"not an MRtrix .tck file"}));
  c.push_back(tractCase("TckNoEnd", "noend.tck",
                        [] { return std::string("mrtrix tracks\ndatatype: Float32LE\n"); }, {"no END line"}));
  c.push_back(tractCase("TckMissingFileEntry", "nofile.tck",
                        [] { return tck("datatype: Float32LE\n", kTckPoints, false); },
                        {"no 'file:' entry"}));
  c.push_back(tractCase("TckMissingDatatype", "nodt.tck", [] { return tck("count: 1\n", kTckPoints); },
                        {"no datatype"}));
  // Legacy VTK cell sections whose counts disagree with their data: vtkPolyDataReader trusted them (a cell
  // claiming 10^8 points read past its buffer and crashed; a negative count or missing cells were accepted).
  const std::string vtkHead = "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
                              "0 0 0\n1 0 0\n2 0 0\n";
  c.push_back(tractCase("VtkLineClaimsHugePointCount", "huge.vtk",
                        [vtkHead] { return vtkHead + "LINES 1 4\n100000000 0 1 2\n"; },
                        {"LINES cell 0 claims 100000000 points"}));
  c.push_back(tractCase("VtkLineNegativePointCount", "neg.vtk",
                        [vtkHead] { return vtkHead + "LINES 1 4\n-3 0 1 2\n"; }, {"a negative count"}));
  c.push_back(tractCase("VtkLinesFewerCellsThanSaid", "few.vtk",
                        [vtkHead] { return vtkHead + "LINES 2 4\n3 0 1 2\n"; }, {"LINES says 2 cells"}));
  c.push_back(tractCase("VtkLinePointIdOutOfRange", "id.vtk",
                        [vtkHead] { return vtkHead + "LINES 1 4\n3 0 1 7\n"; },
                        {"refers to point 7", "POINTS holds 3"}));
  c.push_back(tractCase("VtkPointsMoreThanTheFileHolds", "points.vtk",
                        [] {
                          return std::string("# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                                             "POINTS 999999999 float\n0 0 0\n1 0 0\nLINES 1 3\n2 0 1\n");
                        },
                        {"POINTS says 999999999 points"}));
  c.push_back(tractCase("TckUnsupportedDatatype", "int.tck",
                        [] { return tck("datatype: Int32LE\n", kTckPoints); },
                        {"unsupported .tck datatype 'Int32LE'"}));
  c.push_back(tractCase("TckOffsetPastTheEnd", "offset.tck",
                        [] { return tck("datatype: Float32LE\nfile: . 99999\n", kTckPoints); },
                        {"beyond the end of the file"}));
  c.push_back(tractCase("TckOffsetInsideHeader", "inside.tck",
                        [] { return tck("datatype: Float32LE\nfile: . 4\n", kTckPoints); },
                        {"inside the header"}));
  c.push_back(tractCase("TckNegativeOffset", "negoff.tck",
                        [] { return tck("datatype: Float32LE\nfile: . -40\n", kTckPoints); },
                        {"bad .tck data offset"}));
  c.push_back(tractCase("TckSeparateDataFile", "sep.tck",
                        [] { return tck("datatype: Float32LE\nfile: other.dat 0\n", kTckPoints); },
                        {"separate file"}));
  c.push_back(tractCase("TckTruncatedPointData", "cut.tck",
                        [] {
                          auto s = tck("datatype: Float32LE\n", kTckPoints);
                          return s.substr(0, s.size() - 14);
                        },
                        {"truncated .tck data", "ends inside a triplet"}));
  // Data ending after a NaN separator without the Inf marker is read (MATLAB writers); a streamline with no
  // separator at all is truncated.
  c.push_back(tractCase("TckNoEndMarker", "noinf.tck",
                        [] {
                          return tck("datatype: Float32LE\n", {0, 0, 0, 1, 1, 1});
                        },
                        {"no end-of-file marker", "no NaN separator"}));
  c.push_back(tractCase("TckCountNotANumber", "countnan.tck",
                        [] { return tck("datatype: Float32LE\ncount: many\n", kTckPoints); },
                        {"bad .tck count 'many'"}));
  c.push_back(tractCase(
      "TckPartlyNaNPoint", "halfnan.tck",
      [] {
        return tck("datatype: Float32LE\n", {0, kNaN, 0, 1, 1, 1, kNaN, kNaN, kNaN, kInf, kInf, kInf});
      },
      {"non-finite coordinate in triplet 0"}));
  // ---- .trk
  c.push_back(tractCase("TrkTruncatedHeader", "short.trk", [] { return trk().substr(0, 500); },
                        {"truncated TrackVis header"}));
  c.push_back(tractCase("TrkBadMagic", "magic.trk",
                        [] {
                          auto s = trk();
                          s[0] = 'X';
                          return s;
                        },
                        {"no 'TRACK' magic"}));
  c.push_back(tractCase("TrkBadHeaderSize", "hdr.trk",
                        [] { return trk([](std::string& h) { poke<std::int32_t>(h, 996, 999); }); },
                        {"bad TrackVis header size 999"}));
  c.push_back(tractCase("TrkBadVersion", "version.trk",
                        [] { return trk([](std::string& h) { poke<std::int32_t>(h, 992, 7); }); },
                        {"unsupported TrackVis version 7"}));
  c.push_back(tractCase("TrkBadVoxelOrder", "order.trk",
                        [] {
                          return trk([](std::string& h) {
                            std::memset(h.data() + 440, 0,
                                        64); // no vox_to_ras: the orientation must come from voxel_order
                            std::memcpy(h.data() + 948, "XYZ", 3);
                          });
                        },
                        {"voxel_order 'XYZ'"}));
  c.push_back(tractCase("TrkRepeatedAxisInVoxelOrder", "order2.trk",
                        [] {
                          return trk([](std::string& h) {
                            std::memset(h.data() + 440, 0, 64);
                            std::memcpy(h.data() + 948, "LRS", 3);
                          });
                        },
                        {"voxel_order 'LRS'"}));
  c.push_back(tractCase("TrkZeroVoxelSize", "vs.trk",
                        [] { return trk([](std::string& h) { poke<float>(h, 16, 0.0f); }); },
                        {"bad TrackVis voxel size"}));
  c.push_back(tractCase("TrkNaNVoxelSize", "vsnan.trk",
                        [] { return trk([](std::string& h) { poke<float>(h, 16, kNaN); }); },
                        {"bad TrackVis voxel size"}));
  c.push_back(tractCase("TrkTruncatedPointData", "cut.trk",
                        [] {
                          auto s = trk();
                          return s.substr(0, s.size() - 6);
                        },
                        {"truncated TrackVis data", "claims 2 points"}));
  c.push_back(tractCase("TrkAbsurdCount", "count.trk",
                        [] { return trk([](std::string& h) { poke<std::int32_t>(h, 988, 2147483647); }); },
                        {"count 2147483647 is impossible"}));
  c.push_back(tractCase("TrkNegativeCount", "negcount.trk",
                        [] { return trk([](std::string& h) { poke<std::int32_t>(h, 988, -5); }); },
                        {"negative TrackVis track count"}));
  c.push_back(tractCase("TrkNegativePointCount", "negpts.trk",
                        [] {
                          std::string b;
                          put<std::int32_t>(b, -2);
                          b += floats({1, 1, 1, 3, 3, 3});
                          return trk({}, b);
                        },
                        {"claims -2 points"}));
  c.push_back(tractCase("TrkHugePointCount", "hugepts.trk",
                        [] {
                          std::string b;
                          put<std::int32_t>(b, 2147483647);
                          b += floats({1, 1, 1});
                          return trk({}, b);
                        },
                        {"claims 2147483647 points"}));
  c.push_back(tractCase("TrkTooManyScalars", "scalars.trk",
                        [] { return trk([](std::string& h) { poke<std::int16_t>(h, 36, 1000); }); },
                        {"n_scalars"}));
  c.push_back(tractCase("TrkNaNPoint", "nanpt.trk",
                        [] {
                          std::string b;
                          put<std::int32_t>(b, 2);
                          b += floats({1, kNaN, 1, 3, 3, 3});
                          return trk({}, b);
                        },
                        {"non-finite coordinate in track 0"}));
  c.push_back(tractCase("TractUnknownExtension", "tracts.xyz", [] { return std::string("x"); }, {}));
  // ---- .trk.gz
  c.push_back(tractCase("TrkGzTruncated", "cut.trk.gz",
                        [] {
                          auto z = gzip(trk());
                          return z.substr(0, z.size() / 2);
                        },
                        {"corrupt or truncated gzip data"}));
  c.push_back(tractCase("TrkGzCorrupt", "crc.trk.gz",
                        [] {
                          auto z = gzip(trk());
                          z[z.size() - 6] ^= 0x5a; // the CRC-32 of the uncompressed data
                          return z;
                        },
                        {"corrupt or truncated gzip data"}));
  c.push_back(tractCase("TrkGzNotTrackVis", "text.trk.gz", [] { return gzip(std::string(1200, 'x')); },
                        {"no 'TRACK' magic"}));
  // ---- .trx (zip archives built here by support/zip_builder.h)
  c.push_back(tractCase("TrxNotAZip", "text.trx", [] { return std::string(300, 'x'); },
                        {"not a valid zip archive", "no end-of-central-directory record"}));
  c.push_back(tractCase("TrxTruncatedZip", "cut.trx", [] { return trxZip().substr(0, 150); },
                        {"not a valid zip archive"}));
  c.push_back(tractCase("TrxCentralDirectoryOutside", "cd.trx",
                        [] {
                          auto z = trxZip();
                          poke<std::uint32_t>(z, z.size() - 6, 0x7fffffff); // central directory offset
                          return z;
                        },
                        {"central directory lies outside the file"}));
  c.push_back(tractCase("TrxCorruptDeflate", "deflate.trx",
                        [] {
                          auto z = trxZip({}, true);
                          z[45] ^= 0x77; // inside the deflated header.json
                          return z;
                        },
                        {"header.json"}));
  c.push_back(tractCase("TrxNoHeader", "nohdr.trx",
                        [] { return trxZip([](auto& e) { e.erase(e.begin()); }); }, {"no header.json"}));
  c.push_back(tractCase("TrxOffsetsInconsistent", "offsets.trx",
                        [] { return trxZip([](auto& e) { poke<std::uint32_t>(e[2].data, 4, 9); }); },
                        {"offsets are inconsistent at entry 1"}));
  c.push_back(tractCase("TrxPositionsSizeMismatch", "possize.trx",
                        [] { return trxZip([](auto& e) { e[1].data.resize(24); }); },
                        {"NB_VERTICES 4 needs 48"}));
  c.push_back(tractCase("TrxOffsetsSizeMismatch", "offsize.trx",
                        [] { return trxZip([](auto& e) { e[2].data += std::string(8, '\0'); }); },
                        {"NB_STREAMLINES 2 needs 2 or 3 entries"}));
  c.push_back(tractCase("TrxUnknownPositionsDtype", "dtype.trx",
                        [] { return trxZip([](auto& e) { e[1].name = "positions.3.int32"; }); },
                        {"positions.3.float16|float32|float64"}));
  c.push_back(tractCase("TrxUnknownDataDtype", "dpvdtype.trx",
                        [] { return trxZip([](auto& e) {
                               e.push_back({"dpv/x.float8", "abcd", false});
                             }); },
                        {"unknown dtype 'float8'"}));
  c.push_back(
      tractCase("TrxEntryEscapes", "escape.trx",
                [] {
                  return trxZip([](auto& e) { e.push_back({"dps/../../x.float32", "abcdefgh", false}); });
                },
                {"escapes the archive"}));
  // ---- MRtrix images, NRRD, DSI Studio, FSL dtifit sets (io/formats/formats.h)
  const auto mif = [](const std::string& lines, std::size_t dataBytes, std::size_t offset = 256) {
    std::string h = "mrtrix image\n" + lines + "file: . " + std::to_string(offset) + "\nEND\n";
    h.resize(std::max(h.size(), offset), '\0');
    return h + std::string(dataBytes, '\0');
  };
  const std::string mifGeom = "dim: 4,4,4\nvox: 2,2,2\nlayout: +0,+1,+2\ntransform: 1,0,0,0\n"
                              "transform: 0,1,0,0\ntransform: 0,0,1,0\n";
  c.push_back(infoCase("MrtrixTruncatedData", "short.mif",
                       [=] { return mif(mifGeom + "datatype: Float32LE\n", 100); }, {"truncated", "256"}));
  c.push_back(infoCase("MrtrixUnknownDatatype", "complex.mif",
                       [=] { return mif(mifGeom + "datatype: CFloat32LE\n", 512); },
                       {"unsupported datatype 'CFloat32LE'"}));
  c.push_back(infoCase("MrtrixHeaderWithoutEnd", "noend.mif",
                       [=] { return "mrtrix image\n" + mifGeom + "datatype: Float32LE\nfile: . 256\n"; },
                       {"no END line"}));
  c.push_back(infoCase("MrtrixOffsetBeyondFile", "offset.mif",
                       [=] {
                         return "mrtrix image\n" + mifGeom + "datatype: Float32LE\nfile: . 99999\nEND\n" +
                                std::string(256, '\0');
                       },
                       {"truncated", "offset 99999"}));
  // Fuzz finding: a NaN offset was converted to an integer (undefined behaviour).
  c.push_back(infoCase("MrtrixNanOffset", "nan.mif",
                       [=] { return "mrtrix image\n" + mifGeom + "datatype: Float32LE\nfile: . nan\nEND\n"; },
                       {"file offset nan is not a whole number"}));
  c.push_back(infoCase("MrtrixOffsetInsideHeader", "inside.mif",
                       [=] { return mif(mifGeom + "datatype: Float32LE\n", 256, 8); },
                       {"lies inside the header"}));
  c.push_back(infoCase("MrtrixZeroDimension", "zero.mif",
                       [] {
                         return "mrtrix image\ndim: 4,0,4\nvox: 1,1,1\nlayout: +0,+1,+2\n"
                                "datatype: UInt8\nfile: . 128\nEND\n";
                       },
                       {"whole number >= 1"}));
  c.push_back(infoCase("MrtrixAbsurdDims", "huge.mif",
                       [] {
                         return "mrtrix image\ndim: 100000,100000,100000\nvox: 1,1,1\nlayout: +0,+1,+2\n"
                                "datatype: UInt8\nfile: . 128\nEND\n";
                       },
                       {"absurd"}));
  c.push_back(infoCase("MrtrixDuplicateStride", "stride.mif",
                       [=] { return mif("dim: 4,4,4\nvox: 2,2,2\nlayout: +0,+0,+1\ndatatype: UInt8\n", 64); },
                       {"same rank"}));
  c.push_back(
      infoCase("MrtrixMissingDataFile", "split.mih",
               [=] { return "mrtrix image\n" + mifGeom + "datatype: Float32LE\nfile: gone.dat 0\nEND\n"; },
               {"gone.dat", "does not exist"}));
  c.push_back(infoCase("MrtrixCorruptGzip", "corrupt.mif.gz",
                       [=] {
                         const std::string z = gzip(mif(mifGeom + "datatype: Float32LE\n", 4 * 64));
                         return z.substr(0, z.size() - 12);
                       },
                       {"gzip"}));
  const std::string nrrdHead =
      "NRRD0004\ntype: float\ndimension: 4\nsizes: 6 4 4 4\n"
      "kinds: 3D-symmetric-matrix space space space\nspace: left-posterior-superior\n"
      "space directions: none (2,0,0) (0,2,0) (0,0,2)\nendian: little\n";
  c.push_back(infoCase("NrrdTruncatedData", "short.nrrd",
                       [=] { return nrrdHead + "encoding: raw\n\n" + std::string(100, '\0'); },
                       {"truncated", "1536"}));
  c.push_back(infoCase(
      "NrrdUnknownType", "block.nrrd",
      [] { return std::string("NRRD0004\ntype: block\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n"); },
      {"unsupported type 'block'"}));
  c.push_back(infoCase(
      "NrrdBadSizes", "sizes.nrrd",
      [] { return std::string("NRRD0004\ntype: float\ndimension: 3\nsizes: 2 x 2\nencoding: raw\n\n"); },
      {"sizes entry 'x'"}));
  c.push_back(infoCase("NrrdUnsupportedEncoding", "bz.nrrd", [=] { return nrrdHead + "encoding: bzip2\n\n"; },
                       {"encoding 'bzip2'"}));
  c.push_back(infoCase("NrrdMissingDataFile", "detached.nhdr",
                       [=] { return nrrdHead + "encoding: raw\ndata file: gone.raw\n"; },
                       {"gone.raw", "does not exist"}));
  c.push_back(infoCase("DsiStudioTruncatedMatrix", "cut.src.gz",
                       [] {
                         auto mat = [](const std::string& name, int type, int rows, int cols,
                                       const std::string& payload) {
                           std::string m;
                           put<std::int32_t>(m, type);
                           put<std::int32_t>(m, rows);
                           put<std::int32_t>(m, cols);
                           put<std::int32_t>(m, 0);
                           put<std::int32_t>(m, static_cast<std::int32_t>(name.size() + 1));
                           return m + name + '\0' + payload;
                         };
                         std::string dims, vox;
                         for (short d : {4, 4, 4})
                           put<std::int16_t>(dims, d);
                         for (float v : {2.f, 2.f, 2.f})
                           put<float>(vox, v);
                         const std::string body = mat("dimension", 30, 1, 3, dims) +
                                                  mat("voxel_size", 10, 1, 3, vox) +
                                                  mat("b_table", 10, 4, 1, std::string(16, '\0')) +
                                                  mat("image0", 40, 16, 4, std::string(50, '\0'));
                         return gzip(body);
                       },
                       {"matrix 'image0' is truncated"}));
  const std::string afniHead = "type = integer-attribute\nname = DATASET_RANK\ncount = 2\n 3 1\n\n"
                               "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n 4 4 4\n\n"
                               "type = float-attribute\nname = IJK_TO_DICOM_REAL\ncount = 12\n"
                               " 2 0 0 0 0 2 0 0 0 0 2 0\n\n";
  c.push_back(
      infoCase("AfniComplexBricks", "cx+orig.HEAD",
               [=] { return afniHead + "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 6\n"; },
               {"brick type 6"}));
  c.push_back(
      infoCase("AfniMissingBrik", "nobrik+orig.HEAD",
               [=] { return afniHead + "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 3\n"; },
               {"no .BRIK"}));
  // ---- adversarial cases for the readers of other tools' formats: declared sizes far beyond the file
  // (refused before allocating: run under a memory cap), deflate bombs (refused beyond 256 MiB at more than
  // 100-fold), offsets past the end, NaN or singular transforms, records cut short.
  const std::string mifHuge = "mrtrix image\ndim: 1000,1000,1000\nvox: 1,1,1\nlayout: +0,+1,+2\n"
                              "datatype: Float32LE\nfile: . 256\nEND\n";
  c.push_back(capped(infoCase("MrtrixGzipDeclaringGigabytes", "huge.mif.gz",
                              [=] {
                                std::string h = mifHuge;
                                h.resize(256 + 64, '\0');
                                return gzip(h);
                              },
                              {"truncated", "cannot hold the 4000000256 bytes the header needs"},
                              " --voxel 0,0,0")));
  c.push_back(capped(infoCase("MrtrixDeclaringGigabytes", "huge.mif",
                              [=] {
                                std::string h = mifHuge;
                                h.resize(256 + 64, '\0');
                                return h;
                              },
                              {"truncated", "4000000256"}, " --voxel 0,0,0")));
  c.push_back(capped(infoCase("MrtrixDeflateBomb", "bomb.mif.gz",
                              [] {
                                std::string h = "mrtrix image\ndim: 1024,1024,300\nvox: 1,1,1\n"
                                                "layout: +0,+1,+2\ndatatype: UInt8\nfile: . 256\nEND\n";
                                h.resize(256, '\0');
                                return gzipWithZeros(h, std::uint64_t(300) << 20);
                              },
                              {"deflate bomb"}, " --voxel 0,0,0")));
  c.push_back(infoCase("MrtrixNegativeOffset", "negoffset.mif",
                       [=] {
                         return "mrtrix image\n" + mifGeom + "datatype: Float32LE\nfile: . -64\nEND\n" +
                                std::string(512, '\0');
                       },
                       {"file offset -64 is not a whole number >= 0"}));
  c.push_back(infoCase("MrtrixNanTransform", "nantransform.mif",
                       [=] {
                         return mif("dim: 4,4,4\nvox: 2,2,2\nlayout: +0,+1,+2\ntransform: 1,0,0,0\n"
                                    "transform: 0,nan,0,0\ntransform: 0,0,1,0\ndatatype: Float32LE\n",
                                    256);
                       },
                       {"'transform' is not finite"}));
  c.push_back(infoCase("MrtrixSingularTransform", "singular.mif",
                       [=] {
                         return mif("dim: 4,4,4\nvox: 2,2,2\nlayout: +0,+1,+2\ntransform: 1,0,0,0\n"
                                    "transform: 1,0,0,0\ntransform: 0,0,1,0\ndatatype: Float32LE\n",
                                    256);
                       },
                       {"the transform is singular"}));
  c.push_back(infoCase("MrtrixDwSchemeRowCutShort", "dwcut.mif",
                       [=] {
                         return mif("dim: 2,2,2,2\nvox: 2,2,2\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n"
                                    "dw_scheme: 0,0,0,0\ndw_scheme: 1,0,0\n",
                                    64);
                       },
                       {"a dw_scheme row has 3 numbers (expected 4)"}));
  c.push_back(capped(
      infoCase("MrtrixDetachedDataDeclaringGigabytes", "split.mih",
               [=] {
                 return "mrtrix image\ndim: 1000,1000,1000\nvox: 1,1,1\nlayout: +0,+1,+2\n"
                        "datatype: Float32LE\nfile: split.dat 0\nEND\n";
               },
               {"split.dat", "does not exist"})));
  c.push_back(capped({"MrtrixDetachedGzipDataDeclaringGigabytes",
                      [=](const fs::path& dir) {
                        writeBytes(dir / "split.mih", "mrtrix image\ndim: 1000,1000,1000\nvox: 1,1,1\n"
                                                      "layout: +0,+1,+2\ndatatype: Float32LE\n"
                                                      "file: split.dat.gz 0\nEND\n");
                        writeBytes(dir / "split.dat.gz", gzip(std::string(4096, '\0')));
                        return "info " + q(dir / "split.mih") + " --voxel 0,0,0";
                      },
                      2,
                      {"split.mih", "split.dat.gz", "truncated"}}));
  const std::string nrrdGeom = "space: right-anterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                               "endian: little\n";
  c.push_back(capped(infoCase("NrrdGzipDeclaringGigabytes", "huge.nrrd",
                              [=] {
                                return "NRRD0004\ntype: float\ndimension: 3\nsizes: 1000 1000 1000\n" +
                                       nrrdGeom + "encoding: gzip\n\n" + gzip(std::string(4096, '\0'));
                              },
                              {"truncated", "4000000000 bytes the header needs"}, " --voxel 0,0,0")));
  c.push_back(capped(infoCase("NrrdAsciiDeclaringGigabytes", "huge_ascii.nrrd",
                              [=] {
                                return "NRRD0004\ntype: double\ndimension: 3\nsizes: 1000 1000 1000\n" +
                                       nrrdGeom + "encoding: ascii\n\n1 2 3 4 5 6 7 8\n";
                              },
                              {"ascii data hold 8 numbers, the header needs 1000000000"}, " --voxel 0,0,0")));
  c.push_back(capped(infoCase("NrrdDeflateBomb", "bomb.nrrd",
                              [=] {
                                return "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1024 1024 300\n" +
                                       nrrdGeom + "encoding: gzip\n\n" +
                                       gzipWithZeros("", std::uint64_t(300) << 20);
                              },
                              {"deflate bomb"}, " --voxel 0,0,0")));
  c.push_back(infoCase("NrrdByteSkipPastTheEnd", "skip.nrrd",
                       [=] {
                         return "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\n" + nrrdGeom +
                                "byte skip: 100000\nencoding: raw\n\n" + std::string(32, '\0');
                       },
                       {"truncated", "the header needs 32"}, " --voxel 0,0,0"));
  c.push_back(infoCase("NrrdNanSpaceDirection", "nandir.nrrd",
                       [] {
                         return std::string("NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\n"
                                            "space directions: (nan,0,0) (0,1,0) (0,0,1)\nencoding: raw\n\n") +
                                std::string(32, '\0');
                       },
                       {"'space directions' entry '(nan,0,0)' is not 3 finite numbers"}));
  c.push_back(infoCase("NrrdSingularSpaceDirections", "singular.nrrd",
                       [] {
                         return std::string("NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\n"
                                            "space directions: (1,0,0) (2,0,0) (0,0,1)\nencoding: raw\n\n") +
                                std::string(32, '\0');
                       },
                       {"the space directions are singular"}));
  // NRRD writes "nan" for an unknown spacing: read as 1 mm, with a warning.
  c.push_back({"NrrdNanSpacingIsReported",
               [](const fs::path& dir) {
                 writeBytes(dir / "nanspacing.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\n"
                                                     "spacings: 1 nan 1\nencoding: raw\n\n" +
                                                         std::string(32, '\0'));
                 return "info " + q(dir / "nanspacing.nrrd");
               },
               0,
               {},
               "",
               "spacing 'nan' of axis 1 is not a positive number: 1 mm assumed"});
  c.push_back({"NrrdDetachedDataCutShort",
               [=](const fs::path& dir) {
                 writeBytes(dir / "cut.nhdr", "NRRD0004\ntype: float\ndimension: 3\nsizes: 4 4 4\n" + nrrdGeom +
                                                  "encoding: raw\ndata file: cut.raw\n");
                 writeBytes(dir / "cut.raw", std::string(100, '\0'));
                 return "info " + q(dir / "cut.nhdr") + " --voxel 0,0,0";
               },
               2,
               {"cut.nhdr", "truncated", "256"}});
  const std::string afniGeom = "type = integer-attribute\nname = DATASET_RANK\ncount = 2\n 3 1\n\n"
                               "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 3\n\n";
  const std::string afniAffine = "type = float-attribute\nname = IJK_TO_DICOM_REAL\ncount = 12\n"
                                 " 2 0 0 0 0 2 0 0 0 0 2 0\n\n";
  const auto afni = [](const fs::path& dir, const std::string& head, const std::string& brik,
                       const std::string& brikName = "a+orig.BRIK") {
    writeBytes(dir / "a+orig.HEAD", head);
    writeBytes(dir / brikName, brik);
    return "info " + q(dir / "a+orig.HEAD") + " --voxel 0,0,0";
  };
  c.push_back(capped({"AfniDeclaringGigabytes",
                      [=](const fs::path& dir) {
                        return afni(dir,
                                    afniGeom + afniAffine +
                                        "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n"
                                        " 1000 1000 1000\n",
                                    std::string(4096, '\0'));
                      },
                      2,
                      {"a+orig.HEAD", "truncated", "cannot hold the 4000000000"}}));
  c.push_back(capped({"AfniGzipBrikDeclaringGigabytes",
                      [=](const fs::path& dir) {
                        return afni(dir,
                                    afniGeom + afniAffine +
                                        "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n"
                                        " 1000 1000 1000\n",
                                    gzip(std::string(4096, '\0')), "a+orig.BRIK.gz");
                      },
                      2,
                      {"a+orig.HEAD", "truncated", "cannot hold the 4000000000"}}));
  c.push_back(capped({"AfniDeflateBomb",
                      [=](const fs::path& dir) {
                        return afni(dir,
                                    "type = integer-attribute\nname = DATASET_RANK\ncount = 2\n 3 1\n\n"
                                    "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 0\n\n" +
                                        afniAffine +
                                        "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n"
                                    " 1024 1024 300\n",
                                    gzipWithZeros("", std::uint64_t(300) << 20), "a+orig.BRIK.gz");
                      },
                      2,
                      {"a+orig.BRIK.gz", "deflate bomb"}}));
  for (const auto& [name, matrix, message] : std::vector<std::tuple<std::string, std::string, std::string>>{
           // istream reads no "nan": the attribute is refused as short.
           {"AfniNanTransform", " 2 0 0 0 0 nan 0 0 0 0 2 0", "IJK_TO_DICOM_REAL holds fewer than 12 numbers"},
           {"AfniSingularTransform", " 2 0 0 0 2 0 0 0 0 0 2 0", "singular"}}) {
    c.push_back({name,
                 [=, matrix = matrix](const fs::path& dir) {
                   return afni(dir,
                               afniGeom + "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n"
                                          " 2 2 2\n\ntype = float-attribute\nname = IJK_TO_DICOM_REAL\n"
                                          "count = 12\n" + matrix + "\n",
                               std::string(32, '\0'));
                 },
                 2,
                 {"a+orig.HEAD", message}});
  }
  c.push_back({"AfniAttributeCutShort",
               [=](const fs::path& dir) {
                 return afni(dir,
                             afniGeom + "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n 2 2 2\n\n"
                                        "type = float-attribute\nname = IJK_TO_DICOM_REAL\ncount = 12\n 2 0 0 0 0",
                             std::string(32, '\0'));
               },
               2,
               {"a+orig.HEAD", "IJK_TO_DICOM_REAL holds fewer than 12 numbers"}});
  // DSI Studio: MATLAB v4 matrices (20-byte header, name, values).
  const auto mat4 = [](const std::string& name, int type, int rows, int cols, const std::string& payload) {
    std::string m;
    for (std::int32_t v : {type, rows, cols, 0, static_cast<std::int32_t>(name.size() + 1)})
      put<std::int32_t>(m, v);
    return m + name + '\0' + payload;
  };
  const auto dsiHead = [mat4](float voxel) {
    std::string dims, vox;
    for (short d : {2, 2, 2})
      put<std::int16_t>(dims, d);
    for (float v : {2.f, voxel, 2.f})
      put<float>(vox, v);
    return mat4("dimension", 30, 1, 3, dims) + mat4("voxel_size", 10, 1, 3, vox);
  };
  c.push_back(capped(infoCase("DsiStudioMatrixDeclaringGigabytes", "huge.src.gz",
                              [=] {
                                return gzip(dsiHead(2) + mat4("b_table", 10, 4, 1, std::string(16, '\0')) +
                                            mat4("image0", 10, 46340, 46340, std::string(64, '\0')));
                              },
                              {"matrix 'image0' is truncated", "of 8589582400 bytes"})));
  c.push_back(capped(infoCase("DsiStudioDeflateBomb", "bomb.src.gz",
                              [=] {
                                // A valid header, then one 300 MiB matrix of zeros: the whole file inflates
                                // 1000-fold.
                                std::string h = dsiHead(2) + mat4("b_table", 10, 4, 1, std::string(16, '\0')) +
                                                mat4("image0", 50, 1024 * 1024, 300, "");
                                return gzipWithZeros(h, std::uint64_t(300) << 20);
                              },
                              {"deflate bomb"})));
  c.push_back(infoCase("DsiStudioNanVoxelSize", "nanvox.src.gz",
                       [=] {
                         return gzip(dsiHead(kNaN) + mat4("b_table", 10, 4, 1, std::string(16, '\0')) +
                                     mat4("image0", 10, 4, 2, std::string(32, '\0')));
                       },
                       {"voxel size nan is not positive"}));
  c.push_back(infoCase("DsiStudioMatrixNameCutShort", "cutname.src.gz",
                       [=] { return gzip(dsiHead(2) + mat4("b_table", 10, 4, 1, "").substr(0, 26)); },
                       {"truncated matrix name"}));
  c.push_back(infoCase("DsiStudioFibIndexOutsideVertices", "index.fib.gz",
                       [=] {
                         std::string verts, fa, idx;
                         for (float v : {1.f, 0.f, 0.f, 0.f, 1.f, 0.f})
                           put<float>(verts, v);
                         for (int i = 0; i < 8; ++i) {
                           put<float>(fa, 0.5f);
                           put<float>(idx, i == 5 ? 7.0f : 1.0f);
                         }
                         return gzip(dsiHead(2) + mat4("odf_vertices", 10, 3, 2, verts) +
                                     mat4("fa0", 10, 1, 8, fa) + mat4("index0", 10, 1, 8, idx));
                       },
                       {"index0 holds 7", "outside odf_vertices (2)"}));
  // TRX: zip entries escaping the archive write nothing outside the output; offsets past the end or going
  // back; a singular VOXEL_TO_RASMM; a deflate bomb; header.json cut short.
  c.push_back({"TrxEntryEscapingWritesNothingOutside",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "in");
                 writeBytes(dir / "in" / "evil.trx", trxZip([](auto& e) {
                              e.push_back({"../outside.float32", "abcd", false});
                            }));
                 return "convert " + q(dir / "in" / "evil.trx") + " " + q(dir / "in" / "out.trx");
               },
               2,
               {"evil.trx", "'../outside.float32' escapes the archive"},
               "in/out.trx"});
  c.push_back(tractCase("TrxAbsoluteEntryName", "absolute.trx",
                        [] { return trxZip([](auto& e) { e.push_back({"/tmp/x.float32", "abcd", false}); }); },
                        {"'/tmp/x.float32' escapes the archive"}));
  c.push_back(tractCase("TrxOffsetsGoingBack", "back.trx",
                        [] {
                          return trxZip([](auto& e) {
                            e[0].data = R"({"NB_STREAMLINES": 3, "NB_VERTICES": 4})";
                            e[2].data = std::string("\0\0\0\0\3\0\0\0\1\0\0\0\4\0\0\0", 16);
                          });
                        },
                        {"offsets are inconsistent"}));
  c.push_back(tractCase("TrxOffsetPastTheEnd", "past.trx",
                        [] {
                          return trxZip([](auto& e) {
                            e[2].data = std::string("\0\0\0\0\2\0\0\0\x10\0\0\0", 12);
                          });
                        },
                        {"past.trx", "offsets"}));
  c.push_back(tractCase("TrxSingularVoxelToRas", "singular.trx",
                        [] {
                          return trxZip([](auto& e) {
                            e[0].data = R"({"VOXEL_TO_RASMM": [[0,0,0,0],[0,0,0,0],[0,0,0,0],[0,0,0,1]], )"
                                        R"("DIMENSIONS": [8,8,8], "NB_STREAMLINES": 2, "NB_VERTICES": 4})";
                          });
                        },
                        {"VOXEL_TO_RASMM"}));
  c.push_back(tractCase("TrxHeaderCutShort", "cuthdr.trx",
                        [] {
                          return trxZip([](auto& e) { e[0].data.resize(e[0].data.size() / 2); });
                        },
                        {"header.json"}));
  c.push_back(capped(tractCase("TrxDeflateBomb", "bomb.trx",
                               [] {
                                 return trxZip([](auto& e) {
                                   std::uint32_t crc = 0;
                                   const std::uint64_t n = std::uint64_t(300) << 20;
                                   e.push_back({"dpv/bomb.float32", dtf::test::rawDeflateZeros(n, crc), true, n,
                                                crc});
                                 });
                               },
                               {"dpv/bomb.float32", "deflate bomb"})));
  c.push_back(capped(tractCase("TrxEntryClaimingGigabytes", "claim.trx",
                               [] {
                                 return trxZip([](auto& e) {
                                   e.push_back({"dpv/big.float32", dtf::test::rawDeflate("abcd"), true,
                                                std::uint64_t(3) << 30, 0});
                                 });
                               },
                               {"dpv/big.float32", "corrupt archive"})));
  // bval/bvec tables: binary garbage, numbers beyond double, a record cut in the middle.
  c.push_back(fitCase("BvalBinaryGarbage", dwi, std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), kBvec,
                      {"dwi.bval", "is not a number"}));
  c.push_back(fitCase("BvalBeyondDouble", dwi, "0 1000 1e400 1000 1000 1000 1000 0\n", kBvec,
                      {"dwi.bval", "line 1", "not a finite non-negative number"}));
  c.push_back(fitCase("BvecCutInARow", dwi, kBval,
                      "0 1 0 0 0.7071 0.7071 0 0\n0 0 1 0 0.7071 0 0.7071 0\n0 0 0 1 0 0.7",
                      {"dwi.bvec"}));
  // BIDS layouts: a description that is no object, one that is a folder, a label that walks out.
  const auto bids = [](const fs::path& dir, const std::string& description, bool descriptionIsFolder) {
    fs::create_directories(dir / "ds" / "sub-01" / "dwi");
    if (descriptionIsFolder)
      fs::create_directories(dir / "ds" / "dataset_description.json");
    else
      writeBytes(dir / "ds" / "dataset_description.json", description);
    writeBytes(dir / "ds" / "sub-01" / "dwi" / "sub-01_dwi.nii", dwiNifti().bytes());
    writeBytes(dir / "ds" / "sub-01" / "dwi" / "sub-01_dwi.bval", kBval);
    writeBytes(dir / "ds" / "sub-01" / "dwi" / "sub-01_dwi.bvec", kBvec);
  };
  c.push_back({"BidsDescriptionNotAnObject",
               [=](const fs::path& dir) {
                 bids(dir, "[1, 2, 3]", false);
                 return "bids " + q(dir / "ds") + " " + q(dir / "out") + " participant";
               },
               2,
               {"dataset_description.json", "not a JSON object"},
               "out"});
  c.push_back({"BidsDescriptionIsAFolder",
               [=](const fs::path& dir) {
                 bids(dir, "", true);
                 return "bids " + q(dir / "ds") + " " + q(dir / "out") + " participant";
               },
               2,
               {"dataset_description.json"},
               "out"});
  c.push_back({"BidsParticipantLabelWalkingOut",
               [=](const fs::path& dir) {
                 bids(dir, R"({"Name": "x", "BIDSVersion": "1.8.0"})", false);
                 return "bids " + q(dir / "ds") + " " + q(dir / "out") + " participant --participant-label ../../etc";
               },
               2,
               {"no participant ../../etc"},
               "out"});
  c.push_back({"DtifitSetWithoutV1OrEigenvalues",
               [](const fs::path& dir) {
                 Nifti v2;
                 v2.dims = {4, 4, 4, 3};
                 writeBytes(dir / "dti_V2.nii", v2.bytes());
                 writeBytes(dir / "dti_FA.nii", Nifti().bytes());
                 return "info " + q(dir / "dti");
               },
               2,
               {"dti", "found V2, FA", "missing V1, V3, L1, L2, L3"}});
  // V1 without eigenvalues is a one-population fibre set; all-zero vectors hold no fibre.
  c.push_back({"DtifitV1SetWithoutDirections",
               [](const fs::path& dir) {
                 Nifti v1;
                 v1.dims = {4, 4, 4, 3};
                 writeBytes(dir / "dti_V1.nii", v1.bytes());
                 writeBytes(dir / "dti_FA.nii", Nifti().bytes());
                 return "info " + q(dir / "dti");
               },
               2,
               {"dti_V1.nii", "no fibre direction"}});
  // ---- viewer scripts (parsed completely before a window opens)
  // Fuzz finding: a line of only \v or \f was not blank to the parser but had no words (out-of-bounds read).
  c.push_back(scriptCase("ScriptVerticalTabLine", "\v\f \nfrobnicate\n", {"2:", "frobnicate"}));
  c.push_back(scriptCase("ScriptUnknownCommand", "wait 1\nfrobnicate 3\n", {"2:", "frobnicate"}));
  c.push_back(scriptCase("ScriptWrongArity", "rotate 10\n", {"1:", "usage: rotate"}));
  c.push_back(scriptCase("ScriptNonNumericValue", "# comment\nzoom big\n", {"2:", "'big' is not a number"}));
  c.push_back(scriptCase("ScriptNonIntegerFrames", "wait 2.5\n", {"1:", "not an integer"}));
  c.push_back(scriptCase("ScriptValueOutOfRange", "fa 1.5\n", {"1:", "fa"}));
  c.push_back(scriptCase("ScriptBadOnOff", "split maybe\n", {"1:", "on or off"}));
  c.push_back(scriptCase("ScriptUnknownParam", "set warp 3\n", {"1:", "warp"}));
  // Fuzz finding: a slice index beyond int (here 3.4e18) was converted to int (undefined behaviour).
  c.push_back(scriptCase("ScriptHugeSliceIndex", "surface slice=coronal:3355555555555555555\n",
                         {"1:", "slice index 3355555555555555555 is absurd"}));
  c.push_back(scriptCase("ScriptHugeNegativeSliceIndex", "surface slice=axial:-2e114\n",
                         {"1:", "slice index -2e114 is absurd"}));
  // VTK's Gaussian kernel of a huge sigma does not fit in memory (heap corruption: it aborted).
  c.push_back({"SurfaceHugeSmoothing",
               [](const fs::path& dir) {
                 return "surface " + q(kSample) + " --fa 0.3 --smooth 1e9 -o " + q(dir / "s.ply");
               },
               1,
               {"--smooth must be [0, 20], got 1e9"},
               "s.ply"});
  c.push_back({"SurfaceHugeSliceIndex",
               [](const fs::path& dir) {
                 return "surface " + q(kSample) + " --surface slice=axial:1e300 -o " + q(dir / "s.ply");
               },
               1,
               {"slice index 1e300 is absurd"},
               "s.ply"});
  // A mesh's negative (or, in OBJ, zero) vertex index crashed the normals' computation.
  for (const auto& [name, file, text] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"MeshObjNegativeIndex", "neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n"},
           {"MeshObjZeroIndex", "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"},
           {"MeshPlyNegativeIndex", "neg.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 "
            "-5\n"},
           {"MeshVtkNegativeIndex", "neg.vtk",
            "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0\n1 0 0\n0 1 0\n"
            "POLYGONS 1 4\n3 0 1 -5\n"}}) {
    const std::string f = file, t = text;
    c.push_back({name,
                 [f, t](const fs::path& dir) {
                   writeBytes(dir / f, t);
                   return "surface " + q(kSample) + " --surface mesh=" + q(dir / f) + " -o " +
                          q(dir / "s.ply");
                 },
                 2,
                 {f, "point -5"},
                 "s.ply"});
    c.back().errHas = name == "MeshVtkNegativeIndex"
                          ? std::vector<std::string>{f, "refers to point -5"}
                          : std::vector<std::string>{f, "vertex index is out of range"};
  }
  // vtkOBJReader read an unparsable coordinate as 0: the mesh landed with a vertex moved to the origin.
  c.push_back({"MeshObjNanVertex",
               [](const fs::path& dir) {
                 writeBytes(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
                 return "surface " + q(kSample) + " --surface mesh=" + q(dir / "nan.obj") + " -o " +
                        q(dir / "s.ply");
               },
               2,
               {"nan.obj", "line 2", "'nan' is not a finite number"},
               "s.ply"});
  // Two outputs of one command spelled differently but naming one file: the second write replaced the first.
  c.push_back({"PhantomScalarIsTheOutput",
               [](const fs::path& dir) {
                 return "phantom sphere --size 8 -o " + q(dir / "p.nii.gz") + " --scalar " +
                        q(dir / "." / "p.nii.gz");
               },
               1,
               {"two outputs are the same file", "p.nii.gz"},
               "p.nii.gz"});
  c.push_back({"CheckSheetIsTheFixedBvec",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "sub");
                 return "check " + q(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz") + " --fix-bvec " +
                        q(dir / "s.png") + " --sheet " + q(dir / "sub" / ".." / "s.png");
               },
               1,
               {"two outputs are the same file", "s.png"},
               "s.png"});
  // A pipe where a file is expected is refused: opening it blocked until something wrote to it (a hang).
  const std::string sampleDwi = q(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz"),
                    bvec = q(dtf::test::sourceDir() / "sample_data" / "dwi.bvec");
  for (const auto& [name, file, command, out] :
       std::vector<std::tuple<std::string, std::string, std::string, std::string>>{
           {"NiftiIsAPipe", "p.nii.gz", "info {P}", ""},
           {"MifIsAPipe", "p.mif", "info {P}", ""},
           {"BvalIsAPipe", "p.bval", "fit " + sampleDwi + " --bval {P} --bvec " + bvec + " -o {OUT}", "t.nii.gz"},
           {"BackgroundIsAPipe", "p.nii", "render " + q(kSample) + " --background {P} -o {OUT}", "r.png"}}) {
    const std::string f = file, cmd = command, o = out;
    c.push_back({name,
                 [f, cmd, o](const fs::path& dir) {
                   if (::mkfifo((dir / f).c_str(), 0600) != 0) throw std::runtime_error("mkfifo failed");
                   std::string line = cmd;
                   line.replace(line.find("{P}"), 3, q(dir / f));
                   if (const auto at = line.find("{OUT}"); at != std::string::npos)
                     line.replace(at, 5, q(dir / o));
                   return line;
                 },
                 2,
                 {f, "it is not a regular file (a device, pipe or socket)"},
                 o});
  }
  // A folder where a file is expected is named as one (it was "no such file").
  c.push_back({"TractFileIsAFolder",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "tracts.tck");
                 return "render " + q(kSample) + " --tracts " + q(dir / "tracts.tck") + " -o " +
                        q(dir / "r.png");
               },
               2,
               {"tracts.tck", "it is a folder"},
               "r.png"});
  // vtkPLYReader reads past the end of a short binary PLY (heap corruption: it aborted or segfaulted).
  auto binaryPly = [](bool bigEndian, const std::string& faces, std::size_t keep) {
    std::string h = std::string("ply\nformat binary_") + (bigEndian ? "big" : "little") +
                    "_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face " +
                    faces + "\nproperty list uchar int vertex_indices\nend_header\n";
    std::string body(3 * 12, '\0');
    body += '\3';
    body += std::string(12, '\0');
    return h + body.substr(0, keep);
  };
  // The header's length, so a test can patch the body at a known offset.
  auto plyHeaderSize = [&binaryPly](bool bigEndian) { return binaryPly(bigEndian, "1", 0).size(); };
  for (const auto& [name, text, err] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"MeshPlyBinaryCutInVertices", binaryPly(false, "1", 20), "ends at vertex 1 (truncated)"},
           {"MeshPlyBinaryCutInFaces", binaryPly(true, "1", 36 + 5), "ends at face 0 (truncated)"},
           {"MeshPlyBinaryBillionFaces", binaryPly(false, "1000000000", 49), "ends at face 1 (truncated)"},
           {"MeshPlyAsciiCutInVertices",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n",
            "ends at vertex 2 (truncated)"},
           {"MeshPlyNoEndHeader", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n",
            "no end_header line"},
           // vtkPLYReader also trusts the faces' indices and lengths and the header's properties (a crash).
           {"MeshPlyBinaryIndexOutOfRange",
            binaryPly(false, "1", 36 + 13)
                .replace(36 + 1 + plyHeaderSize(false) + 8, 4, std::string("\x3f\x42\x0f\x00", 4)),
            "vertex index is out of range in face 0: 999999 (the file has 3 vertices)"},
           {"MeshPlyLittleEndianBodyDeclaredBig",
            binaryPly(true, "1", 36 + 13)
                .replace(36 + 1 + plyHeaderSize(true), 4, std::string("\x01\x00\x00\x00", 4)),
            "vertex index is out of range in face 0: 16777216"},
           {"MeshPlyNoVertices",
            "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 0\nproperty list uchar int vertex_indices\nend_header\n",
            "no vertices (element vertex 0)"},
           {"MeshPlyFaceOfNoVertices",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0\n",
            "face 0 has 0 vertices (a face needs 3)"},
           {"MeshPlyNoZ",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n",
            "no scalar property 'z'"},
           {"MeshPlyFacesWithoutIndices",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            "no vertex_indices list"}}) {
    const std::string t = text;
    c.push_back({name,
                 [t](const fs::path& dir) {
                   writeBytes(dir / "cut.ply", t);
                   return "surface " + q(kSample) + " --surface mesh=" + q(dir / "cut.ply") + " -o " +
                          q(dir / "s.obj");
                 },
                 2,
                 {"cut.ply", err},
                 "s.obj"});
  }
  c.push_back({"ScriptMissingFile",
               [](const fs::path& dir) { return "view --script " + q(dir / "none.dtfs"); },
               2,
               {"none.dtfs"}});
  // ---- crossing-fibre files (peaks: x y z per peak; bedpostx: dyadsN + mean_fNsamples)
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  c.push_back(infoCase(
      "FibresPartlyNanPeak", "peaks.nii",
      [nan] {
        return peaksNifti(6, {{1, nan}}).bytes();
      },
      {"peak 1 is partly NaN"}, " --layout mrtrix-peaks"));
  c.push_back(infoCase(
      "FibresInfPeak", "peaks.nii",
      [inf] {
        return peaksNifti(6, {{3 * 8 + 3, inf}}).bytes();
      },
      {"peak 2 holds Inf"}, " --layout mrtrix-peaks"));
  c.push_back(infoCase("FibresAllZeroLength", "peaks.nii",
                       [] { return peaksNifti(6, {}, 0.0f).bytes(); }, {"no fibre direction", "zero-length"},
                       " --layout dipy-peaks"));
  c.push_back(infoCase("FibresWrongVolumeCount", "peaks.nii",
                       [] { return peaksNifti(7, {}).bytes(); }, {"has 7 volumes", "multiple of 3"},
                       " --layout mrtrix-peaks"));
  c.push_back({"BedpostxMismatchedGrids",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "bpx");
                 writeBytes(dir / "bpx" / "dyads1.nii", peaksNifti(3, {}).bytes());
                 Nifti f;
                 f.dims = {3, 2, 2};
                 f.data = floats(std::vector<float>(12, 0.5f));
                 writeBytes(dir / "bpx" / "mean_f1samples.nii", f.bytes());
                 return "info " + q(dir / "bpx");
               },
               2,
               {"mean_f1samples.nii", "its grid differs from", "dyads1.nii"}});
  c.push_back({"BedpostxMissingFractions",
               [](const fs::path& dir) {
                 fs::create_directories(dir / "bpx");
                 writeBytes(dir / "bpx" / "dyads1.nii", peaksNifti(3, {}).bytes());
                 return "info " + q(dir / "bpx" / "dyads1.nii");
               },
               2,
               {"dyads1.nii", "has no fractions file", "mean_f1samples"}});
  // Two peaks in 6 volumes are triplets like peaks, not a positive semi-definite tensor: never read as a tensor.
  c.push_back({"TwoPeaksAreNotATensor",
               [](const fs::path& dir) {
                 writeBytes(dir / "two_peaks.nii", peaksNifti(6, {}).bytes());
                 return "surface " + q(dir / "two_peaks.nii") + " --slice axial -o " + q(dir / "s.ply");
               },
               2,
               {"two_peaks.nii", "two fibre peaks", "not a tensor"},
               "s.ply"});
  // `profile`: a bundle whose streamlines have no length (a single point, one repeated point), a scalar image
  // whose affine is singular, a bundle cut short.
  auto profileCase = [](std::string name, std::string tracts, std::string tractBytes, std::string image,
                        std::string imageBytes, std::vector<std::string> errHas) {
    return Case{name,
                [=](const fs::path& dir) {
                  writeBytes(dir / tracts, tractBytes);
                  writeBytes(dir / image, imageBytes);
                  return "profile " + q(dir / tracts) + " --scalar v=" + q(dir / image) + " -o " +
                         q(dir / "p.tsv") + " --plot " + q(dir / "p.png");
                },
                2, errHas, "p.tsv"};
  };
  Nifti scalar;
  c.push_back(profileCase("ProfileStreamlinesWithoutLength", "nolength.tck",
                          tck("count: 2\ndatatype: Float32LE\n",
                              {0, 0, 0, kNaN, kNaN, kNaN, 2, 2, 2, 2, 2, 2, kNaN, kNaN, kNaN, kInf, kInf, kInf}),
                          "v.nii", scalar.bytes(), {"nolength.tck", "none of the bundle's 2 streamlines"}));
  Nifti singular;
  std::memset(singular.srow, 0, sizeof singular.srow);
  singular.pixdim[0] = singular.pixdim[1] = singular.pixdim[2] = 0;
  c.push_back(profileCase("ProfileScalarWithSingularAffine", "ok.tck", tck("count: 1\ndatatype: Float32LE\n", kTckPoints),
                          "singular.nii", singular.bytes(), {"singular.nii", "singular"}));
  c.push_back(profileCase("ProfileTruncatedTracts", "cut.tck",
                          tck("count: 1\ndatatype: Float32LE\n", {0, 0, 0, 1, 1}), "v.nii", scalar.bytes(),
                          {"cut.tck"}));
  // ROI selection: bad regions and region set files exit 2 naming the spec or the file; nothing is written.
  c.push_back(selectCase("SelectNanRadius", "--include 0,0,0,nan", {"0,0,0,nan", "radius"}));
  c.push_back(selectCase("SelectNegativeRadius", "--include 0,0,0,-3", {"0,0,0,-3", "radius"}));
  c.push_back(selectCase("SelectInvertedBox", "--exclude box:5,5,5,0,0,0", {"box:5,5,5,0,0,0", "inverted"}));
  c.push_back(selectCase("SelectBoxOfFiveNumbers", "--include box:1,2,3,4,5", {"box:1,2,3,4,5", "six numbers"}));
  c.push_back(selectCase("SelectSphereOfThreeNumbers", "--include 1,2,3", {"'1,2,3'", "four numbers"}));
  c.push_back(selectCase("SelectMissingMask", "--include DIR/nothing.nii.gz", {"nothing.nii.gz", "no such file"}));
  c.push_back(selectCase("SelectSingularMaskAffine", "--include DIR/flat.nii", {"flat.nii"}, "", 2,
                         [](const fs::path& dir) {
                           Nifti n;
                           std::memset(n.srow, 0, sizeof n.srow);
                           n.data = floats(std::vector<float>(64, 1.0f));
                           writeBytes(dir / "flat.nii", n.bytes());
                         }));
  c.push_back(selectCase("SelectLabelNotInImage", "--include DIR/labels.nii:4", {"labels.nii", "label 4 is not in"},
                         "", 2, [](const fs::path& dir) {
                           Nifti n;
                           std::vector<float> v(64, 0.0f);
                           v[5] = 3;
                           n.data = floats(v);
                           writeBytes(dir / "labels.nii", n.bytes());
                         }));
  c.push_back(selectCase("SelectMalformedRoiJson", "--roi DIR/roi.json", {"roi.json", "not valid JSON"}, "{\"format\": "));
  c.push_back(selectCase("SelectRoiOfAnotherVersion", "--roi DIR/roi.json", {"roi.json", "version 7"},
                         R"({"format": "dtfabric-regions", "version": 7, "regions": []})"));
  c.push_back(selectCase("SelectRoiUnknownMember", "--roi DIR/roi.json", {"roi.json", "unknown member \"colour\""},
                         R"({"format": "dtfabric-regions", "version": 1, "regions": [{"kind": "include", "shape": "sphere", "centre": [0, 0, 0], "radius": 2, "colour": "red"}]})"));
  c.push_back(selectCase("SelectRoiSphereWithoutRadius", "--roi DIR/roi.json", {"roi.json", "region 0", "radius"},
                         R"({"format": "dtfabric-regions", "version": 1, "regions": [{"kind": "include", "shape": "sphere", "centre": [0, 0, 0]}]})"));
  c.push_back(selectCase("SelectRoiBadKind", "--roi DIR/roi.json", {"roi.json", "region 0", "kind"},
                         R"({"format": "dtfabric-regions", "version": 1, "regions": [{"kind": "maybe", "shape": "box", "min": [0, 0, 0], "max": [1, 1, 1]}]})"));
  c.push_back(selectCase("SelectRoiNotASet", "--roi DIR/roi.json", {"roi.json", "not a region set"}, "[1, 2, 3]"));
  c.push_back(selectCase("SelectAsGroupIntoTck", "--include 0,0,0,1 --as-group g", {"--as-group", ".trx"}, "", 1));
  return c;
}

// Names the case in gtest output instead of dumping its bytes.
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

class MalformedInput : public ::testing::TestWithParam<Case> {};

TEST_P(MalformedInput, IsRefusedCleanly) {
  const Case& c = GetParam();
  const fs::path dir = dtf::test::scratchDir();
  const std::string args = c.setup(dir);
#if defined(__SANITIZE_ADDRESS__)
  const std::string cap =
      "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:hard_rss_limit_mb=2560:max_allocation_size_mb=1024\" ";
#elif defined(__SANITIZE_THREAD__)
  const std::string cap; // TSan reserves its shadow memory at start: an address-space cap breaks it
#else
  const std::string cap = "ulimit -v 2097152; ";
#endif
  const CliResult r = runDtfabric(args, dir, c.capMemory ? cap : "");
  if (c.capMemory) {
    EXPECT_EQ(r.err.find("out of memory"), std::string::npos) << "an allocation failed:\n" << r.err;
  }
  EXPECT_LT(r.exitCode, 128) << "killed by signal " << r.exitCode - 128 << "\n" << r.err;
  EXPECT_EQ(r.exitCode, c.exitCode) << "dtfabric " << args << "\nstdout:\n"
                                    << r.out << "\nstderr:\n"
                                    << r.err;
  for (const auto& s : c.errHas)
    EXPECT_NE(r.err.find(s), std::string::npos) << "stderr lacks '" << s << "':\n" << r.err;
  // Only dtfabric's message: nifticlib's own "** ERROR ..." lines (printed at its default debug level for the
  // empty, truncated, random, bad sizeof_hdr and corrupt gzip cases) are silenced.
  EXPECT_EQ(r.err.find("** "), std::string::npos) << "a library's message leaked:\n" << r.err;
  if (c.exitCode != 0) {
    EXPECT_NE(r.err.find("dtfabric "), std::string::npos) << r.err;
  }
  if (!c.outHas.empty()) {
    EXPECT_NE(r.out.find(c.outHas), std::string::npos) << "stdout lacks '" << c.outHas << "':\n" << r.out;
  }
  if (!c.output.empty()) {
    EXPECT_FALSE(fs::exists(dir / c.output)) << c.output << " was written";
  }
  // No temporary output left behind either (AtomicOutput names them beside the target).
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
}

INSTANTIATE_TEST_SUITE_P(Catalogue, MalformedInput, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

// An existing output is kept byte for byte unless --force is given.
TEST(OutputProtection, ExistingOutputsNeedForce) {
  const fs::path dir = dtf::test::scratchDir();
  writeBytes(dir / "keep.nii", "precious");
  writeBytes(dir / "keep.png", "precious");
  for (const std::string& args :
       {"phantom constant --size 8 -o " + q(dir / "keep.nii"),
        "phantom constant --size 8 -o " + q(dir / "new.nii") + " --scalar " + q(dir / "keep.nii"),
        "render " + q(kSample) + " -o " + q(dir / "keep.png")}) {
    const CliResult r = runDtfabric(args, dir);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("keep."), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(" exists (use --force"), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(readBytes(dir / "keep.nii"), "precious") << args;
    EXPECT_EQ(readBytes(dir / "keep.png"), "precious") << args;
    EXPECT_FALSE(fs::exists(dir / "new.nii")) << args;
  }
  const CliResult r = runDtfabric("phantom constant --size 8 --force -o " + q(dir / "keep.nii"), dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(readBytes(dir / "keep.nii"), "precious");
}

// A symbolic link whose target is missing is an existing output too: writing would replace the link.
TEST(OutputProtection, ADanglingLinkNeedsForce) {
  const fs::path dir = dtf::test::scratchDir();
  fs::create_symlink(dir / "nowhere.png", dir / "link.png");
  CliResult r = runDtfabric("render " + q(kSample) + " --size 32x32 -o " + q(dir / "link.png"), dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("link.png exists (use --force"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.png")));
  r = runDtfabric("render " + q(kSample) + " --size 32x32 --force -o " + q(dir / "link.png"), dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir / "link.png")));
}

// An output name of up to 255 bytes (the file system's limit) is written: its temporary twin is cut short.
TEST(OutputProtection, ALongOutputNameIsWritten) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path out = dir / (std::string(251, 'n') + ".png");
  const CliResult r = runDtfabric("render " + q(kSample) + " --size 32x32 -o " + q(out), dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}
// `view --script`: screenshot and camera-save lines are checked before a window opens (so this runs without
// a display): an existing file needs --force, an input is refused whatever --force says.
TEST(OutputProtection, ViewScriptOutputsAreCheckedBeforeTheWindow) {
  const fs::path dir = dtf::test::scratchDir();
  ASSERT_EQ(runDtfabric("phantom constant --size 8 -o " + q(dir / "t.nii"), dir).exitCode, 0);
  const std::string volume = readBytes(dir / "t.nii");
  writeBytes(dir / "old.png", "precious");
  writeBytes(dir / "old.camera", "precious");
  struct Run {
    std::string script, args, errHas;
  };
  for (const Run& run :
       {Run{"fa 0.3\nscreenshot " + (dir / "old.png").string() + "\n", "",
            "fig.dtfs:2: " + (dir / "old.png").string() + " exists (use --force"},
        Run{"camera-save " + (dir / "old.camera").string() + "\n", "",
            "fig.dtfs:1: " + (dir / "old.camera").string() + " exists (use --force"},
        Run{"camera-save --force " + (dir / "t.nii").string() + "\n", q(dir / "t.nii") + " --force",
            "fig.dtfs:1: refusing to write " + (dir / "t.nii").string() + ": it is an input file"},
        Run{"load " + (dir / "t.nii").string() + "\ncamera-save --force " + (dir / "t.nii").string() + "\n",
            "--force",
            "fig.dtfs:2: refusing to write " + (dir / "t.nii").string() + ": it is an input file"}}) {
    writeBytes(dir / "fig.dtfs", run.script);
    const CliResult r = runDtfabric("view " + run.args + " --script " + q(dir / "fig.dtfs"), dir);
    EXPECT_EQ(r.exitCode, 2) << run.script << r.err;
    EXPECT_NE(r.err.find(run.errHas), std::string::npos) << run.script << r.err;
    EXPECT_EQ(readBytes(dir / "old.png"), "precious");
    EXPECT_EQ(readBytes(dir / "old.camera"), "precious");
    EXPECT_EQ(readBytes(dir / "t.nii"), volume);
  }
  // `view --force` lets the existing files through the check (the window then opens, or without a display
  // the viewer stops with exit code 3).
  writeBytes(dir / "fig.dtfs", "screenshot " + (dir / "old.png").string() + "\ncamera-save " +
                                   (dir / "old.camera").string() + "\nquit\n");
  const CliResult r = runDtfabric("view --force --script " + q(dir / "fig.dtfs"), dir);
  EXPECT_NE(r.exitCode, 2) << r.err;
  EXPECT_EQ(r.err.find(" exists (use --force"), std::string::npos) << r.err;
}

// Inputs are never outputs, whatever --force says.
TEST(OutputProtection, AnInputIsNeverOverwritten) {
  const fs::path dir = dtf::test::scratchDir();
  ASSERT_EQ(runDtfabric("phantom constant --size 8 -o " + q(dir / "t.nii"), dir).exitCode, 0);
  const std::string before = readBytes(dir / "t.nii");
  struct Run {
    std::string args;
    int exitCode;
  };
  // Stand-ins for a mesh and a mask: the refusal comes before they are read.
  writeBytes(dir / "m.ply", "mesh");
  writeBytes(dir / "x.vtk", "mask");
  const std::string t = q(dir / "t.nii"), m = q(dir / "m.ply"), x = q(dir / "x.vtk");
  for (const Run& run : {Run{"render " + t + " --force -o " + t, 1},
                         Run{"surface " + t + " --surface mesh=" + m + " --force -o " + m, 2},
                         Run{"track " + t + " --mask " + x + " --force -o " + x, 2}}) {
    const CliResult r = runDtfabric(run.args, dir);
    EXPECT_EQ(r.exitCode, run.exitCode) << run.args << "\n" << r.err;
    EXPECT_TRUE(r.err.find("is the input") != std::string::npos ||
                r.err.find("it is an input file") != std::string::npos)
        << run.args << "\n"
        << r.err;
    EXPECT_EQ(readBytes(dir / "t.nii"), before) << run.args;
    EXPECT_EQ(readBytes(dir / "m.ply"), "mesh") << run.args;
    EXPECT_EQ(readBytes(dir / "x.vtk"), "mask") << run.args;
  }
}

// A write that falls short fails the command, names the output and leaves nothing behind: no output, no
// temporary file. The shell's file size limit stands in for a full disk (SIGXFSZ ignored, a write beyond the
// limit fails with EFBIG as one on a full disk fails with ENOSPC). Every output runs without the limit first,
// so each one is known to be larger than the limit.
TEST(OutputProtection, AShortWriteFailsAndLeavesNothing) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path whole = dir / "whole";
  fs::create_directories(whole);
  const std::string sample = q(kSample);
  ASSERT_EQ(runDtfabric("track " + sample + " --select 300 -o " + q(dir / "in.tck"), dir).exitCode, 0);
  struct Run {
    std::string output, command; // the command writes `output` where it says {}
  };
  const std::vector<Run> runs = {
      {"s.ply", "surface " + sample + " --surface slice=axial -o {}"},
      {"s.obj", "surface " + sample + " --surface slice=axial -o {}"},
      {"s.vtp", "surface " + sample + " --surface slice=axial -o {}"},
      {"t.nii", "phantom sphere --size 24 -o {}"},
      {"f.nii.gz", "fit " + q(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz") + " -o {}"},
      {"t2.nii", "phantom sphere --size 24 --nifti2 -o {}"},
      {"t.mif", "phantom sphere --size 24 -o {}"},
      {"t.nrrd", "phantom sphere --size 24 -o {}"},
      {"r.png", "render " + sample + " --size 256x256 -o {}"},
      {"l.vtk", "convert " + q(dir / "in.tck") + " {}"},
      {"l.vtp", "convert " + q(dir / "in.tck") + " {}"},
      {"l.trk", "convert " + q(dir / "in.tck") + " {} --reference " + sample},
      {"l.tck", "convert " + q(dir / "in.tck") + " {}"},
      {"l.trx", "convert " + q(dir / "in.tck") + " {} --reference " + sample},
      {"p.tsv", "profile " + q(dir / "in.tck") + " --scalar fa --tensor " + sample + " --nodes 400 -o {}"},
      {"p.png", "profile " + q(dir / "in.tck") + " --scalar fa --tensor " + sample + " --force -o " +
                    q(dir / "p_table.tsv") + " --plot {}"},
      {"p.svg", "profile " + q(dir / "in.tck") + " --scalar fa --tensor " + sample + " --force -o " +
                    q(dir / "p_table.tsv") + " --plot {}"},
  };
  constexpr std::uintmax_t kLimitBytes = 16 * 512; // `ulimit -f 16`: blocks of 512 bytes in sh (dash)
  for (const Run& run : runs) {
    auto to = [&](const fs::path& out) {
      std::string c = run.command;
      return c.replace(c.find("{}"), 2, q(out));
    };
    const CliResult ok = runDtfabric(to(whole / run.output), dir);
    ASSERT_EQ(ok.exitCode, 0) << run.command << "\n" << ok.err;
    ASSERT_GT(fs::file_size(whole / run.output), 2 * kLimitBytes) << run.output << " is too small to test";
    const CliResult r = runDtfabric(to(dir / run.output), dir, "trap '' XFSZ; ulimit -f 16; ");
    EXPECT_EQ(r.exitCode, 2) << to(dir / run.output) << "\n" << r.err;
    EXPECT_NE(r.err.find(run.output), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("ERR|"), std::string::npos) << "VTK's own error dump leaked:\n" << r.err;
    EXPECT_FALSE(fs::exists(dir / run.output)) << run.output << " was left, incomplete";
    for (const auto& e : fs::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
  }
}

// The files of one result land together or not at all: when a later output of a command fails, the earlier
// ones, already complete in their temporary files, are removed too, and a folder the write made is gone.
// The file size limit fails the large second output (the constant phantom's gzip tensors and the corrected
// table are small); a folder in place of bedpostx's last file fails its fourth write.
TEST(OutputProtection, AFailedOutputLeavesNoneOfItsSet) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string dwi = q(dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz");
  auto noTemporaries = [](const fs::path& d) {
    for (const auto& e : fs::recursive_directory_iterator(d))
      EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << e.path();
  };
  const std::string limit = "trap '' XFSZ; ulimit -f 16; ";
  CliResult r = runDtfabric(
      "phantom constant --size 32 -o " + q(dir / "t.nii.gz") + " --scalar " + q(dir / "s.nii"), dir, limit);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("s.nii"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "t.nii.gz")) << "the tensors were left without their scalar field";
  ASSERT_EQ(runDtfabric(
                "phantom constant --size 32 -o " + q(dir / "t.nii.gz") + " --scalar " + q(dir / "s.nii"), dir)
                .exitCode,
            0); // the same command without the limit writes both
  EXPECT_TRUE(fs::exists(dir / "t.nii.gz") && fs::exists(dir / "s.nii"));

  r = runDtfabric("check " + dwi + " --fix-bvec " + q(dir / "f.bvec") + " --sheet " + q(dir / "c.png"), dir,
                  limit);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("c.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "f.bvec")) << "the corrected table was left without its sheet";
  EXPECT_EQ(r.err.find("wrote "), std::string::npos) << "a write was reported that did not land:\n" << r.err;

  fs::create_directories(dir / "bp" / "mean_f2samples.nii.gz");
  r = runDtfabric("phantom crossing --size 24 --layout bedpostx --force -o " + q(dir / "bp"), dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("mean_f2samples.nii.gz"), std::string::npos) << r.err;
  for (const char* f : {"dyads1.nii.gz", "mean_f1samples.nii.gz", "dyads2.nii.gz"})
    EXPECT_FALSE(fs::exists(dir / "bp" / f)) << f << " was left in a bedpostx folder without the rest";
  r = runDtfabric("phantom crossing --size 24 --layout bedpostx -o " + q(dir / "new_bp"), dir,
                  "trap '' XFSZ; ulimit -f 2; ");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_FALSE(fs::exists(dir / "new_bp")) << "an empty bedpostx folder was left";

  // A missing folder fails before the fit, which can take minutes with --bootstrap, and writes nothing.
  r = runDtfabric("fit " + dwi + " --bootstrap 5 --cone " + q(dir / "nope" / "c.nii.gz") + " -o " +
                      q(dir / "fit.nii.gz"),
                  dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("nope/c.nii.gz: directory does not exist"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bootstrap: "), std::string::npos) << "the fit ran before the output was checked:\n"
                                                          << r.err;
  EXPECT_FALSE(fs::exists(dir / "fit.nii.gz"));
  noTemporaries(dir);
}

// --force replaces only what the command writes: a regular file, or a movie's folder of frames; never a
// pipe or device (renamed over, it was lost) nor a folder holding other files (a movie removed them).
TEST(OutputProtection, ForceReplacesOnlyFilesAndFrameFolders) {
  const fs::path dir = dtf::test::scratchDir();
  ASSERT_EQ(runDtfabric("phantom constant --size 8 -o " + q(dir / "t.nii"), dir).exitCode, 0);
  const std::string t = q(dir / "t.nii");
  for (const std::string name : {"fifo.png", "fifo.ply", "fifo.nii"}) {
    ASSERT_EQ(::mkfifo((dir / name).c_str(), 0600), 0) << name;
    const std::string args = name == "fifo.png"   ? "render " + t + " --size 32x32"
                             : name == "fifo.ply" ? "surface " + t + " --slice axial"
                                                  : "phantom constant --size 8";
    const CliResult r = runDtfabric(args + " --force -o " + q(dir / name), dir);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_fifo(dir / name)) << name;
  }
  const fs::path project = dir / "project";
  fs::create_directories(project / "sub");
  writeBytes(project / "notes.txt", "precious");
  CliResult r = runDtfabric("movie " + t + " --size 32x32 --frames 1 --sweep axial --force -o " + q(project) + "/", dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("not only the frame_NNNN.png"), std::string::npos) << r.err;
  EXPECT_EQ(readBytes(project / "notes.txt"), "precious");
  EXPECT_TRUE(fs::is_directory(project / "sub"));
  // A folder of frames a movie wrote is replaced.
  const fs::path frames = dir / "frames";
  ASSERT_EQ(runDtfabric("movie " + t + " --size 32x32 --frames 2 --sweep axial -o " + q(frames) + "/", dir).exitCode, 0);
  r = runDtfabric("movie " + t + " --size 32x32 --frames 1 --sweep axial --force -o " + q(frames) + "/", dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(frames / "frame_0000.png"));
  EXPECT_FALSE(fs::exists(frames / "frame_0001.png"));
}

// No GL context (EGL finds no vendor library) or no GL 4.5 (Mesa told to offer 3.3): a clear message and
// exit code 3, no output file.
TEST(Environment, RenderWithoutGl45ContextExitsWith3) {
  const fs::path dir = dtf::test::scratchDir();
  struct Env {
    const char* name;
    const char* value;
    const char* errHas;
  };
  for (const Env& env : {Env{"__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json", "EGL"},
                         Env{"MESA_GL_VERSION_OVERRIDE", "3.3", "4.5 core"}}) {
    ASSERT_EQ(setenv(env.name, env.value, 1), 0);
    const CliResult r = runDtfabric("render " + q(kSample) + " --size 64x64 -o " + q(dir / "x.png"), dir);
    unsetenv(env.name);
    if (r.exitCode == 0 && std::string(env.name) == "MESA_GL_VERSION_OVERRIDE") {
      fs::remove(dir / "x.png"); // not Mesa: the variable is ignored
      continue;
    }
    EXPECT_EQ(r.exitCode, 3) << env.name << "\n" << r.err;
    EXPECT_NE(r.err.find("GL error: cannot create a headless OpenGL 4.5 core context"), std::string::npos)
        << env.name << "\n"
        << r.err;
    EXPECT_NE(r.err.find(env.errHas), std::string::npos) << env.name << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.png")) << env.name;
  }
}

// A tensor volume wider than GL_MAX_3D_TEXTURE_SIZE (32767 voxels, the largest NIfTI-1 axis; llvmpipe allows
// 2048, GPU drivers at most 16384) but only 3 MiB: the render stops with a GL error (exit code 3) naming the
// grid and the limit, and writes nothing. Real GPU memory exhaustion cannot be forced reliably; this is the
// same path (GlError from the tensor upload).
TEST(Environment, VolumeBeyondThe3DTextureLimitExitsWith3) {
  const fs::path dir = dtf::test::scratchDir();
  Nifti n;
  n.dims = {32767, 2, 2, 6};
  std::vector<float> v(n.values(), 0.0f);
  const std::size_t voxels = 32767 * 4;
  for (int c : {0, 3, 5})
    std::fill_n(v.begin() + static_cast<std::ptrdiff_t>(c * voxels), voxels, 1e-3f);
  n.data = floats(v);
  writeBytes(dir / "wide.nii", n.bytes());
  const CliResult r =
      runDtfabric("render " + q(dir / "wide.nii") + " --layout fsl --surface slice=axial:0 --size 64x64 -o " +
                      q(dir / "x.png"),
                  dir);
  if (r.err.find("cannot create a headless OpenGL") != std::string::npos &&
      !dtf::test::envFlag("DTF_REQUIRE_GL"))
    GTEST_SKIP() << r.err;
  EXPECT_EQ(r.exitCode, 3) << r.err;
  EXPECT_NE(r.err.find("32767x2x2 exceeds this GL's 3D texture size limit"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

} // namespace
