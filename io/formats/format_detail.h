// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to dtf_io: the per-format readers and writers behind the dispatch in io/formats/formats.cpp, and
// the pieces they share. Other modules use io/formats/tensor_io.h and io/formats/formats.h. Every reader
// throws InputError whose message starts with the file name.
#pragma once

#include "io/formats/format_guess.h"
#include "io/formats/sample_types.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace dtf::io::detail {

// --- NIfTI (io/formats/nifti_io.cpp)
VolumeHeader readNiftiHeader(const std::string& path);
ScalarVolume readNiftiScalarVolume(const std::string& path, VolumeHeader* header);
LoadedTensors readNiftiTensorVolume(const std::string& path, TensorLayout layout);
void writeNiftiTensorVolume(const std::string& path, const TensorField& field, TensorLayout layout,
                            int niftiVersion);
void writeNiftiScalarVolume(const std::string& path, const ScalarVolume& v, int niftiVersion,
                            const std::string& descrip);

// Fills out.field (and layout, reason, counts, warnings) from a 6-component volume whose components are in
// the on-disk order of `layout` (Auto: detected as for NIfTI, `preferred` when ambiguous). out.header must
// be filled. Throws InputError when every voxel is NaN.
void tensorsFromComponents(LoadedTensors& out, const ScalarVolume& raw, TensorLayout layout, bool fiveD,
                           const std::string& path, TensorLayout preferred);

// Stores a world tensor at voxel i (zero or non-finite: counted and left invalid).
inline void storeWorldTensor(LoadedTensors& out, std::size_t i, const glm::dmat3& m) {
  bool finite = true, zero = true;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      finite = finite && std::isfinite(m[c][r]);
      zero = zero && m[c][r] == 0;
    }
  if (!finite) {
    ++out.nanVoxels;
    return;
  }
  if (zero) return;
  out.field.tensors[i] = SymTensor::fromMat(m);
  out.field.valid[i] = 1;
  const double m2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  if (!(m[0][0] > 0 && m2 > 0 && glm::determinant(m) > 0)) ++out.nonPositiveVoxels;
}

// --- Tensor or fibre peaks? (io/formats/component_evidence.cpp)
enum class ComponentKind { Tensor, Peaks, Ambiguous, Neither };
// What a volume with 3K components per voxel (interleaved) can be, from an even sample of up to 8,000 of
// its voxels with data. With 6 components a tensor must be positive semi-definite (smallest eigenvalue
// >= -1% of the largest) in nearly every voxel, read in FSL or MRtrix order: >= 90% is a tensor, < 50% is
// not. Peaks come in triplets that only peaks show (a triplet zero or NaN beside a present one in >= 1% of
// voxels, unit vectors in >= 90%), or that peaks usually show (two thirds of the components signed,
// amplitudes sorted strongest first in >= 99% of voxels with several). A tensor fit with peak-only triplets
// is Ambiguous (the caller refuses and asks for a layout); between 50% and 90% peak-only triplets decide
// for peaks, else the tensor stands; below 50% (or 9+ components) any peak evidence makes Peaks, none
// Neither. Approximate by nature: thresholds chosen on real MRtrix/DIPY peaks and tensors (every layout).
struct ComponentEvidence {
  ComponentKind kind = ComponentKind::Neither;
  std::size_t voxels = 0;                 // voxels examined
  double psdFsl = 0, psdMrtrix = 0;       // fraction positive semi-definite in each order (6 components)
  double tripletGaps = 0;                 // fraction with a triplet zero or NaN beside a present one
  double partialNan = 0;                  // fraction with a partly-NaN or Inf triplet
  double unitTriplets = 0;                // fraction whose present triplets are all unit vectors
  double orderedAmplitudes = 0;           // of voxels with 2+ present triplets: lengths non-increasing
  double signedComponents = 0;            // fraction of components negative in >= 5% of their voxels
  std::string evidence;                   // the figures above in words
};
ComponentEvidence componentEvidence(const ScalarVolume& raw);

// Throws InputError "PATH: PROBLEM": every reader's message starts with the file name.
[[noreturn]] inline void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

// `s` without leading and trailing blanks, tabs and carriage returns.
inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// --- MRtrix images (io/formats/mrtrix_io.cpp)
struct MrtrixImage {
  VolumeHeader header;                       // dims (all axes), grid (axes 0-2), datatype name, scaling
  ScalarVolume volume;                       // axes 3.. flattened into components (axis 3 fastest)
  std::vector<std::vector<double>> dwScheme; // dw_scheme rows (gx gy gz b, scanner frame), may be empty
};
MrtrixImage readMrtrix(const std::string& path, bool withData);
// Writes `v` (components become axis 3) as float32 in the given stride layout (one signed rank per axis,
// e.g. {-1, 2, 3, 4} or {4, 1, 2, 3}: MRtrix's "layout", smallest |rank| fastest, negative = stored in
// reverse); empty = {1, 2, 3, 4}. `extraHeader` lines ("key: value") are added verbatim. Atomic.
void writeMrtrix(const std::string& path, const ScalarVolume& v, const std::vector<int>& strides = {},
                 const std::vector<std::string>& extraHeader = {});

// --- NRRD (io/formats/nrrd_io.cpp)
struct NrrdVolume {
  VolumeHeader header;
  ScalarVolume volume; // non-spatial axis (at most one) as components
  std::string kind;    // kind of the non-spatial axis ("3D-symmetric-matrix", ...), or ""
  glm::dmat3 measurementFrame{1.0};
  bool hasMeasurementFrame = false;
  bool lps = false;           // the header's space was LPS (already converted to RAS in the grid)
  glm::dmat3 spaceToRas{1.0}; // the space's axes -> RAS (diag(-1,-1,1) for LPS, diag(-1,1,1) for LAS)
};
NrrdVolume readNrrd(const std::string& path, bool withData);
LoadedTensors nrrdTensors(const std::string& path);
// Writes world tensors as an attached, gzip-encoded NRRD (RAS space, 3D-masked-symmetric-matrix first,
// identity measurement frame). Atomic. Throws InputError.
void writeNrrdTensors(const std::string& path, const TensorField& field);

// --- FSL dtifit eigen-systems (io/formats/dtifit_io.cpp)
// The basename of a dtifit set from `path` (basename itself or any member file), or "" when none.
std::string dtifitBasename(const std::string& path);
// The file of `member` ("V1", "L1", "FA", ...) of the set `base` (.nii.gz or .nii), or "" when absent.
std::string dtifitMemberFile(const std::string& base, const std::string& member);
LoadedTensors readDtifit(const std::string& path);
VolumeHeader dtifitHeader(const std::string& path);

// A DWI's signal with the gradient table stored in the same file, as stored: io/diffusion/dwi.cpp checks it
// and turns it into a Dwi.
struct StoredGradients {
  ScalarVolume signal;                // components = volumes
  std::vector<double> bvals;          // s/mm^2
  std::vector<glm::dvec3> directions; // as stored (not normalised)
  glm::dmat3 directionsToWorld{1.0};  // stored frame -> world RAS (identity for a scanner-frame table)
  std::string table;                  // the entry that held the table: "dw_scheme", "b_table"
};

// --- DSI Studio (io/formats/dsi_studio.cpp)
ScalarVolume readDsiSrcSignal(const std::string& path, VolumeHeader* header);
StoredGradients readDsiSrc(const std::string& path);
VolumeHeader dsiHeader(const std::string& path);

// The signal and the gradient table stored in the file (MRtrix dw_scheme, DSI Studio b_table);
// io/formats/formats.cpp. Throws InputError when the file holds no table or a single volume.
StoredGradients readStoredGradients(const std::string& path, const FormatGuess& format);

// --- AFNI (io/formats/afni_io.cpp): bricks as components; header only when !withData.
ScalarVolume readAfni(const std::string& path, VolumeHeader* header, bool withData);
std::string afniBrikFile(const std::string& head);

// --- shared byte helpers
// Deflate expands at most about 1032:1, so a gzip file of N bytes holds at most N * kMaxDeflateRatio bytes.
constexpr std::size_t kMaxDeflateRatio = 1032;
// Beyond kBombFloorBytes inflated, a gzip file inflating more than kBombRatio-fold is refused as a deflate
// bomb (image data compress a few-fold; only near-empty volumes come close, and those are small).
constexpr std::size_t kBombFloorBytes = std::size_t(256) << 20;
constexpr std::size_t kBombRatio = 100;
// Throws InputError "PATH: WHAT..." when data of `stored` bytes (gzip when `gz`) cannot give the `need` bytes
// a header declares: too short ("is truncated"), or a gzip stream that would have to inflate more than
// kBombRatio-fold beyond kBombFloorBytes ("a deflate bomb"). `note` is added after the sizes. Called before
// anything is allocated.
void checkInflatable(const std::string& path, const std::string& what, std::size_t stored, bool gz,
                     unsigned long long need, const std::string& note = "");
// The same for the file `file` (gzip when it starts with the gzip magic).
void checkInflatable(const std::string& path, const std::string& what, const std::string& file,
                     unsigned long long need, const std::string& note = "");
// Reads a whole file, inflating it when it starts with the gzip magic. `limit` bytes at most (throws
// InputError beyond). Throws InputError naming the file for unreadable or corrupt gzip files.
// `expect` (0: unknown) is the inflated size a header declares: it sizes the buffer (libdeflate inflates
// whole buffers; see io/formats/gzip.h).
std::vector<std::uint8_t> readFileBytes(const std::string& path, bool* wasGzip = nullptr,
                                        std::size_t limit = std::size_t(1) << 33, std::size_t expect = 0);
// Throws InputError naming `path` when it exists but is a device, pipe or socket: opening a pipe blocks
// until something writes to it (nifticlib, stdio and zlib all would wait forever).
void refuseSpecialFile(const std::string& path);
// Whether the file begins with the gzip magic (1f 8b): compression is told from the content, not the name.
// False for a file that cannot be opened (the reader then names that).
bool startsWithGzipMagic(const std::string& path);
// The file's bytes as stored (no inflation); at most `limit` bytes (throws InputError beyond, or when
// the file is missing or unreadable).
std::vector<std::uint8_t> readRawFile(const std::string& path, std::size_t limit = std::size_t(1) << 40);
// Reads up to `n` leading bytes (inflated when gzip). Never throws; empty when unreadable.
std::vector<std::uint8_t> peekFileBytes(const std::string& path, std::size_t n);
// Writes bytes to `path` (gzip when `gz`) through a temporary file renamed into place. Throws InputError.
void writeFileBytes(const std::string& path, const std::vector<std::uint8_t>& bytes, bool gz);

bool endsWith(const std::string& s, const std::string& suffix);
// More values than this are refused before allocating.
constexpr long long kMaxValues = 1LL << 31;

} // namespace dtf::io::detail
