// SPDX-License-Identifier: GPL-3.0-or-later
// Fibre-set readers and writers (see fibre_io.h).
#include "io/formats/fibre_io.h"

#include "io/formats/atomic_file.h"
#include "io/formats/dsi_studio.h"
#include "io/formats/format_detail.h"
#include "io/formats/formats.h"
#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <regex>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

constexpr const char* kMarker = "dtfabric fibres layout=";

using detail::ComponentEvidence;
using detail::componentEvidence;
using detail::ComponentKind;
using detail::fail;

std::string fmt(double v, int precision = 3) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", precision, v);
  return b;
}

// The voxel-frame -> world rotation of a layout (identity for the world-frame MRtrix peaks).
glm::dmat3 frameToWorld(const Grid& g, FibreLayout l) {
  if (l == FibreLayout::MrtrixPeaks) return glm::dmat3(1.0);
  glm::dmat3 r = g.rotation();
  if ((l == FibreLayout::Bedpostx || l == FibreLayout::DtifitV1) &&
      glm::determinant(glm::dmat3(g.voxelToWorld)) > 0)
    r[0] = -r[0];
  return r;
}

std::string voxelText(const Grid& g, std::size_t v) {
  const auto nx = static_cast<std::size_t>(g.dims.x), ny = static_cast<std::size_t>(g.dims.y);
  return std::to_string(v % nx) + "," + std::to_string((v / nx) % ny) + "," + std::to_string(v / (nx * ny));
}

// Peaks as stored (no frame applied): vectors of length = amplitude. NaN triplets and zero vectors are
// absent; Inf or a partly NaN triplet is an error.
FibreSet peaksAsStored(const std::string& path, const ScalarVolume& raw, bool& hasNan) {
  if (raw.components < 3 || raw.components % 3 != 0)
    fail(path, "has " + std::to_string(raw.components) +
                   " volumes; a peaks file holds 3 per peak (x, y, z), so a multiple of 3");
  const int k = raw.components / 3;
  FibreSet s = makeFibreSet(raw.grid, k);
  hasNan = false;
  const std::size_t nv = raw.grid.voxelCount();
  for (std::size_t v = 0; v < nv; ++v)
    for (int n = 0; n < k; ++n) {
      const float* c =
          &raw.data[v * static_cast<std::size_t>(raw.components) + static_cast<std::size_t>(3 * n)];
      const int nans = std::isnan(c[0]) + std::isnan(c[1]) + std::isnan(c[2]);
      if (nans == 3) {
        hasNan = true;
        continue;
      }
      if (nans > 0)
        fail(path, "voxel " + voxelText(raw.grid, v) + " peak " + std::to_string(n + 1) + " is partly NaN");
      if (std::isinf(c[0]) || std::isinf(c[1]) || std::isinf(c[2]))
        fail(path, "voxel " + voxelText(raw.grid, v) + " peak " + std::to_string(n + 1) + " holds Inf");
      const glm::vec3 d(c[0], c[1], c[2]);
      const float len = glm::length(d);
      if (!(len > 0.0f)) continue;
      if (!std::isfinite(len))
        fail(path, "voxel " + voxelText(raw.grid, v) + " peak " + std::to_string(n + 1) + " is too long (" +
                       fmt(len) + ")");
      Fibre& f = s.fibres[v * static_cast<std::size_t>(k) + static_cast<std::size_t>(n)];
      f.direction = d / len;
      // Unit peaks (DIPY writes no amplitude) are 1 up to float rounding: rounding differences must not
      // reorder them, so they count as exactly 1.
      f.amplitude = std::abs(len - 1.0f) < 1e-4f ? 1.0f : len;
    }
  if (s.occupiedVoxels() == 0) fail(path, "holds no fibre direction (every vector is zero-length or NaN)");
  return s;
}

void rotate(FibreSet& s, const glm::dmat3& m) {
  for (Fibre& f : s.fibres)
    if (f.amplitude > 0.0f) f.direction = glm::vec3(glm::normalize(m * glm::dvec3(f.direction)));
}

bool nearIdentity(const glm::dmat3& m) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(m[c][r] - (c == r ? 1.0 : 0.0)) > 1e-6) return false;
  return true;
}

std::string markerLayout(const std::string& descrip) {
  if (descrip.rfind(kMarker, 0) != 0) return "";
  std::string name = descrip.substr(std::string(kMarker).size());
  return name.substr(0, name.find(' '));
}

LoadedFibres readPeaks(const std::string& path, const FormatGuess& format, FibreLayout layout) {
  LoadedFibres out;
  ScalarVolume raw = readScalarVolume(path, format, &out.header);
  out.files.push_back(path);
  out.warnings = out.header.warnings;
  bool hasNan = false;
  FibreSet stored = peaksAsStored(path, raw, hasNan);
  raw = {};
  const Grid& g = stored.grid;
  if (layout == FibreLayout::Auto) {
    const std::string marked = markerLayout(out.header.descrip);
    const glm::dmat3 r = g.rotation();
    if (marked == "mrtrix-peaks" || marked == "dipy-peaks") {
      layout = parseFibreLayout(marked);
      out.layoutReason = "written by dtfabric: descrip names layout " + marked;
    } else if (nearIdentity(r)) {
      layout = hasNan ? FibreLayout::MrtrixPeaks : FibreLayout::DipyPeaks;
      out.layoutReason =
          std::to_string(stored.maxFibres) + " peaks (" + std::to_string(3 * stored.maxFibres) +
          " volumes); the voxel axes are the world axes on this " + g.orientationCode() +
          " grid, so the frame does not matter; " +
          (hasNan ? "NaN for absent peaks as MRtrix writes" : "zeros for absent peaks as DIPY writes");
    } else {
      const Coherence world = fibreCoherence(stored), voxel = fibreCoherence(stored, r);
      const bool isWorld = world.score >= voxel.score;
      layout = isWorld ? FibreLayout::MrtrixPeaks : FibreLayout::DipyPeaks;
      out.layoutReason =
          std::to_string(stored.maxFibres) + " peaks (" + std::to_string(3 * stored.maxFibres) +
          " volumes), frame not recorded in the file; fibre coherence (neighbouring single-fibre "
          "voxels whose peaks both run along the step between them, " +
          std::to_string(world.pairs) + " pairs): world frame " + fmt(100 * world.score) + "%, voxel frame " +
          fmt(100 * voxel.score) + "% => " + (isWorld ? "world" : "voxel") + " frame (" +
          fibreLayoutName(layout) + ")";
      const double hi = std::max(world.score, voxel.score), lo = std::min(world.score, voxel.score);
      if (world.pairs < 200 || hi < lo * 1.05 + 1e-9)
        out.warnings.push_back("the peaks' frame is uncertain (coherence " + fmt(100 * world.score) +
                               "% vs " + fmt(100 * voxel.score) + "%); assumed " + fibreLayoutName(layout) +
                               ", use --layout mrtrix-peaks or dipy-peaks to override");
    }
  } else {
    out.layoutReason = std::string("given explicitly (") + fibreLayoutName(layout) + ")";
  }
  if (layout == FibreLayout::Bedpostx)
    fail(path, "--layout bedpostx needs a bedpostx folder or one of its dyadsN files");
  rotate(stored, frameToWorld(g, layout));
  normaliseFibres(stored);
  out.set = std::move(stored);
  out.layout = layout;
  return out;
}

std::string existing(const fs::path& folder, const std::string& stem) {
  for (const char* ext : {".nii.gz", ".nii"}) {
    fs::path p = folder / (stem + ext);
    if (fs::exists(p)) return p.string();
  }
  return "";
}

const std::regex& bedpostxName() {
  static const std::regex r(R"((dyads\d+|mean_f\d+samples)\.nii(\.gz)?)");
  return r;
}

// The basename of the FSL dtifit set that `path` names, by its basename or its V1 file, when the set has V1
// but none of L1-L3, else "". Its other members (FA, MD, ...) stay scalar volumes.
std::string dtifitV1Base(const std::string& path) {
  const std::string base = dtifitSetOf(path);
  if (base.empty()) return "";
  const std::string v1 = detail::dtifitMemberFile(base, "V1");
  std::error_code ec;
  if (v1.empty() || (fs::is_regular_file(path, ec) && !fs::equivalent(path, v1, ec))) return "";
  for (const char* l : {"L1", "L2", "L3"})
    if (!detail::dtifitMemberFile(base, l).empty()) return "";
  return base;
}

LoadedFibres readDtifitV1(const std::string& base) {
  LoadedFibres out;
  out.layout = FibreLayout::DtifitV1;
  const std::string v1 = detail::dtifitMemberFile(base, "V1");
  ScalarVolume v = readScalarVolume(v1, &out.header);
  out.files.push_back(v1);
  out.warnings = out.header.warnings;
  if (v.components != 3)
    fail(v1, "has " + std::to_string(v.components) + " volumes; a dtifit V1 file holds 3 (x, y, z)");
  std::string found = "V1";
  for (const char* m : {"V2", "V3", "FA", "MD", "MO", "S0"})
    if (!detail::dtifitMemberFile(base, m).empty()) found += std::string(", ") + m;
  if (const std::string faPath = detail::dtifitMemberFile(base, "FA"); !faPath.empty()) {
    ScalarVolume fa = readScalarVolume(faPath);
    if (fa.components != 1)
      fail(faPath, "has " + std::to_string(fa.components) + " volumes; a dtifit FA file holds 1");
    if (!fa.grid.sameAs(v.grid)) fail(faPath, "its grid differs from " + v1);
    out.files.push_back(faPath);
    out.fa = std::move(fa);
  }
  bool hasNan = false;
  FibreSet s = peaksAsStored(v1, v, hasNan);
  v = {};
  for (Fibre& f : s.fibres)
    if (f.amplitude > 0.0f) f.amplitude = 1.0f; // V1 is unit; its length carries no amplitude
  const bool negateX = glm::determinant(glm::dmat3(s.grid.voxelToWorld)) > 0;
  rotate(s, frameToWorld(s.grid, FibreLayout::DtifitV1));
  normaliseFibres(s);
  out.set = std::move(s);
  out.layoutReason =
      "FSL dtifit set " + base + ": found " + found + "; no L1-L3, so V1 is one population of amplitude 1" +
      (out.fa.data.empty() ? " (no FA file to pair)" : ", FA paired") + "; FSL frame: voxel axes" +
      (negateX ? ", x negated (det(affine) > 0)" : " (det(affine) < 0: x not negated)");
  return out;
}

LoadedFibres readDsiStudioFibres(const std::string& path) {
  LoadedFibres out;
  out.layout = FibreLayout::DsiStudio;
  DsiStudioFib fib = readDsiStudioFib(path);
  const std::size_t k = std::min<std::size_t>(3, fib.fraction.size());
  out.header.path = path;
  out.header.niftiVersion = 0;
  out.header.grid = fib.grid;
  out.header.dims = {fib.grid.dims.x, fib.grid.dims.y, fib.grid.dims.z, static_cast<int>(3 * k)};
  out.header.datatypeName = "MATLAB v4";
  out.header.affineSource = "none in the file: DSI Studio's LPS voxel axes, centred";
  out.files.push_back(path);
  out.warnings.emplace_back(
      "DSI Studio files carry no scanner position: LPS voxel axes assumed, centred on 0");
  FibreSet s = makeFibreSet(fib.grid, static_cast<int>(k));
  const std::size_t nv = fib.grid.voxelCount();
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t n = 0; n < k; ++n) {
      const float a = fib.fraction[n].data[v];
      const float* d = &fib.directions[n].data[v * 3];
      if (!(a > 0.0f) || !std::isfinite(a)) continue;
      s.fibres[v * k + n] = {glm::vec3(d[0], d[1], d[2]), a};
    }
  normaliseFibres(s);
  if (s.occupiedVoxels() == 0) fail(path, "holds no fibre (every fa0 is zero)");
  out.set = std::move(s);
  out.fa = std::move(fib.dtiFa);
  out.layoutReason = "DSI Studio FIB: " + std::to_string(k) + " of " + std::to_string(fib.fraction.size()) +
                     " populations (fa0.." + "fa" + std::to_string(k - 1) +
                     " as amplitudes, index0.. into odf_vertices as directions), LPS voxel axes, centred; " +
                     (out.fa.data.empty() ? "no dti_fa to pair" : "dti_fa paired as FA");
  return out;
}

LoadedFibres readBedpostx(const std::string& path) {
  LoadedFibres out;
  fs::path folder = fs::is_directory(path) ? fs::path(path) : fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  std::vector<std::string> dyads;
  for (int n = 1; n <= 16; ++n) {
    std::string d = existing(folder, "dyads" + std::to_string(n));
    if (d.empty()) break;
    dyads.push_back(d);
  }
  if (dyads.empty()) fail(path, "no dyads1.nii.gz in " + folder.string() + " (not a bedpostx folder)");
  FibreSet set;
  for (std::size_t n = 0; n < dyads.size(); ++n) {
    const std::string fname = "mean_f" + std::to_string(n + 1) + "samples";
    const std::string fpath = existing(folder, fname);
    if (fpath.empty()) fail(dyads[n], "has no fractions file " + (folder / (fname + ".nii.gz")).string());
    VolumeHeader hd, hf;
    ScalarVolume d = readScalarVolume(dyads[n], &hd);
    ScalarVolume f = readScalarVolume(fpath, &hf);
    out.files.push_back(dyads[n]);
    out.files.push_back(fpath);
    if (d.components != 3)
      fail(dyads[n],
           "has " + std::to_string(d.components) + " volumes; a bedpostx dyads file holds 3 (x, y, z)");
    if (f.components != 1)
      fail(fpath, "has " + std::to_string(f.components) + " volumes; a bedpostx fractions file holds 1");
    if (!d.grid.sameAs(f.grid)) fail(fpath, "its grid differs from " + dyads[n]);
    if (n == 0) {
      out.header = hd;
      set = makeFibreSet(d.grid, static_cast<int>(dyads.size()));
    } else if (!d.grid.sameAs(set.grid)) {
      fail(dyads[n], "its grid differs from " + dyads[0]);
    }
    const glm::dmat3 m = frameToWorld(set.grid, FibreLayout::Bedpostx);
    for (std::size_t v = 0; v < set.grid.voxelCount(); ++v) {
      const float* c = &d.data[v * 3];
      const float frac = f.data[v];
      if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
        fail(dyads[n], "voxel " + voxelText(set.grid, v) + " holds NaN/Inf");
      if (!std::isfinite(frac)) fail(fpath, "voxel " + voxelText(set.grid, v) + " holds NaN/Inf");
      const glm::dvec3 dir(c[0], c[1], c[2]);
      const double len = glm::length(dir);
      if (!(frac > 0.0f) || !(len > 1e-6)) continue;
      Fibre& fb = set.fibres[v * static_cast<std::size_t>(set.maxFibres) + n];
      fb.direction = glm::vec3(glm::normalize(m * (dir / len)));
      fb.amplitude = frac;
    }
  }
  if (set.occupiedVoxels() == 0) fail(path, "holds no fibre (every dyad is zero-length or its fraction 0)");
  normaliseFibres(set);
  out.set = std::move(set);
  out.layout = FibreLayout::Bedpostx;
  out.warnings = out.header.warnings;
  return out;
}

bool isBedpostxPath(const std::string& path) {
  if (fs::is_directory(path)) return !existing(path, "dyads1").empty();
  return std::regex_match(fs::path(path).filename().string(), bedpostxName());
}

} // namespace

glm::dmat3 fibreFrameToWorld(const Grid& g, FibreLayout l) {
  return frameToWorld(g, l);
}

const char* fibreLayoutName(FibreLayout l) {
  switch (l) {
  case FibreLayout::MrtrixPeaks:
    return "mrtrix-peaks";
  case FibreLayout::DipyPeaks:
    return "dipy-peaks";
  case FibreLayout::Bedpostx:
    return "bedpostx";
  case FibreLayout::DsiStudio:
    return "dsi-studio";
  case FibreLayout::DtifitV1:
    return "dtifit-v1";
  default:
    return "auto";
  }
}

bool isFibreLayoutName(const std::string& n) {
  return n == "mrtrix-peaks" || n == "dipy-peaks" || n == "bedpostx" || n == "fibres-auto";
}

FibreLayout parseFibreLayout(const std::string& n) {
  if (n == "mrtrix-peaks") return FibreLayout::MrtrixPeaks;
  if (n == "dipy-peaks") return FibreLayout::DipyPeaks;
  if (n == "bedpostx") return FibreLayout::Bedpostx;
  if (n == "auto" || n == "fibres-auto") return FibreLayout::Auto;
  throw UsageError("unknown fibre layout '" + n + "' (expected mrtrix-peaks, dipy-peaks, bedpostx or auto)");
}

bool looksLikeFibres(const std::string& path, std::string* reason) {
  return looksLikeFibres(path, detectFormat(path), reason);
}

bool looksLikeFibres(const std::string& path, const FormatGuess& g, std::string* reason) {
  auto say = [&](bool r, const std::string& why) {
    if (reason) *reason = why;
    return r;
  };
  if (isBedpostxPath(path)) return say(true, "a bedpostx folder or file name");
  if (fs::is_directory(path)) return say(false, "a folder without dyads1.nii.gz"); // the readers say why
  if (const std::string base = dtifitV1Base(path); !base.empty())
    return say(true, "an FSL dtifit set " + base + " with V1 but no L1-L3");
  if (g.format == FileFormat::DsiStudioFib) return say(true, "a DSI Studio FIB file (" + g.reason + ")");
  if (g.format != FileFormat::Nifti)
    return say(false, std::string(formatName(g.format)) + ", not a NIfTI peaks file"); // its reader says more
  VolumeHeader h = readHeader(path, g);
  if (!markerLayout(h.descrip).empty()) return say(true, "written by dtfabric as a fibre set");
  long long comps = 1;
  for (std::size_t i = 3; i < h.dims.size(); ++i)
    comps *= h.dims[i];
  if (h.dims.size() < 4 || comps < 6 || comps % 3 != 0 || h.intentCode == 1005)
    return say(false, "not 4D with 6, 9, 12, ... volumes (one peak needs --layout)");
  if (comps > 48) return say(false, std::to_string(comps) + " volumes: more than 16 peaks, a DWI");
  std::string stem = path;
  for (const char* s : {".nii.gz", ".nii"})
    if (stem.size() > std::strlen(s) && stem.compare(stem.size() - std::strlen(s), std::strlen(s), s) == 0) {
      stem.resize(stem.size() - std::strlen(s));
      break;
    }
  if (fs::exists(stem + ".bval")) return say(false, "has a sibling .bval (a DWI)");
  // Decided by what the values can be (detail::componentEvidence), not by their signs: sign-normalised peaks
  // have none. Six components that fit a tensor are left to the tensor reader (which refuses a file that fits
  // both).
  const ComponentEvidence e = componentEvidence(readScalarVolume(path, g));
  const std::string peaks = std::to_string(comps / 3) + " peaks";
  switch (e.kind) {
  case ComponentKind::Peaks:
    return say(true, "triplets like fibre peaks (" + peaks + "; " + e.evidence + ")");
  case ComponentKind::Ambiguous:
    return say(false, "fits both a tensor and " + peaks + " (" + e.evidence + ")");
  case ComponentKind::Tensor:
    return say(false, "positive semi-definite like a tensor (" + e.evidence + ")");
  case ComponentKind::Neither:
    break;
  }
  return say(false, "not like fibre peaks (" + e.evidence + ")");
}

LoadedFibres readFibres(const std::string& path, FibreLayout layout) {
  return readFibres(path, detectFormat(path), layout);
}

LoadedFibres readFibres(const std::string& path, const FormatGuess& format, FibreLayout layout) {
  {
    if (layout == FibreLayout::Bedpostx || (layout == FibreLayout::Auto && isBedpostxPath(path))) {
      LoadedFibres out = readBedpostx(path);
      out.layoutReason = layout == FibreLayout::Bedpostx
                             ? "given explicitly (bedpostx)"
                             : "bedpostx file names (dyadsN + mean_fNsamples), FSL frame: voxel axes" +
                                   std::string(glm::determinant(glm::dmat3(out.set.grid.voxelToWorld)) > 0
                                                   ? ", x negated (det(affine) > 0)"
                                                   : " (det(affine) < 0: x not negated)");
      return out;
    }
    if (fs::is_directory(path)) fail(path, "is a folder without dyads1.nii.gz (not a bedpostx folder)");
    if (layout == FibreLayout::DsiStudio ||
        (layout == FibreLayout::Auto && format.format == FileFormat::DsiStudioFib))
      return readDsiStudioFibres(path);
    if (layout == FibreLayout::DtifitV1 || layout == FibreLayout::Auto)
      if (const std::string base = dtifitV1Base(path); !base.empty()) return readDtifitV1(base);
    if (layout == FibreLayout::DtifitV1) fail(path, "is not an FSL dtifit set with V1 and no L1-L3");
    return readPeaks(path, format, layout);
  }
}

void writeFibres(const std::string& path, const FibreSet& set, FibreLayout layout, int niftiVersion) {
  if (layout == FibreLayout::Auto) throw UsageError("a fibre layout to write must be named (not auto)");
  if (layout == FibreLayout::DsiStudio || layout == FibreLayout::DtifitV1)
    throw UsageError(std::string("fibre layout ") + fibreLayoutName(layout) + " is read only");
  const auto k = static_cast<std::size_t>(set.maxFibres);
  const std::size_t nv = set.grid.voxelCount();
  const glm::dmat3 toDisk = glm::transpose(frameToWorld(set.grid, layout)); // orthonormal: inverse
  if (layout == FibreLayout::Bedpostx) {
    std::error_code ec;
    const bool existed = fs::exists(path, ec);
    fs::create_directories(path, ec);
    if (ec) fail(path, "cannot create the bedpostx folder: " + ec.message());
    struct RemoveNewFolder { // declared before the batch, so it runs after the batch removed its files
      const std::string& path;
      bool keep;
      ~RemoveNewFolder() {
        std::error_code e;
        if (!keep) fs::remove(path, e); // only if empty: a folder this write made and filled with nothing
      }
    } cleanup{path, existed};
    OutputBatch batch; // every dyads/mean_f pair or none
    for (std::size_t n = 0; n < k; ++n) {
      ScalarVolume d(set.grid, 3), f(set.grid, 1);
      for (std::size_t v = 0; v < nv; ++v) {
        const Fibre& fb = set.fibres[v * k + n];
        if (!(fb.amplitude > 0.0f)) continue;
        const glm::vec3 u(toDisk * glm::dvec3(fb.direction));
        for (int c = 0; c < 3; ++c)
          d.data[v * 3 + static_cast<std::size_t>(c)] = u[c];
        f.data[v] = fb.amplitude;
      }
      const std::string num = std::to_string(n + 1);
      writeScalarVolume((fs::path(path) / ("dyads" + num + ".nii.gz")).string(), d, niftiVersion,
                        std::string(kMarker) + "bedpostx");
      writeScalarVolume((fs::path(path) / ("mean_f" + num + "samples.nii.gz")).string(), f, niftiVersion,
                        std::string(kMarker) + "bedpostx");
    }
    batch.commit();
    cleanup.keep = true;
    return;
  }
  const float absent = layout == FibreLayout::MrtrixPeaks ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
  ScalarVolume out(set.grid, static_cast<int>(3 * k), absent);
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t n = 0; n < k; ++n) {
      const Fibre& fb = set.fibres[v * k + n];
      if (!(fb.amplitude > 0.0f)) continue;
      const glm::vec3 u(toDisk * glm::dvec3(fb.direction) * static_cast<double>(fb.amplitude));
      for (int c = 0; c < 3; ++c)
        out.data[v * 3 * k + 3 * n + static_cast<std::size_t>(c)] = u[c];
    }
  writeScalarVolume(path, out, niftiVersion, std::string(kMarker) + fibreLayoutName(layout));
}

} // namespace dtf::io
