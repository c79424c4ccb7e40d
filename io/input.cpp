// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/input.h"

#include "io/model/error.h"

#include <filesystem>

namespace fs = std::filesystem;

namespace dtf::io {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool isTractogramName(const std::string& path) {
  for (const char* e : {".tck", ".trk", ".trk.gz", ".trx", ".vtk", ".vtp"})
    if (endsWith(path, e)) return true;
  return false;
}

OpenedInput opened(const InputRequest& r, InputKind kind, std::string reason, const FormatGuess& format) {
  OpenedInput in;
  in.path = r.path;
  in.kind = kind;
  in.reason = std::move(reason);
  in.format = format;
  return in;
}

// A 4D volume that is not a tensor file: a DWI whose gradient files lie beside it.
OpenedInput openBySiblings(const InputRequest& r, const FormatGuess& g, const VolumeHeader& h) {
  OpenedInput in = opened(r, InputKind::Dwi, "", g);
  in.bval = gradientSibling(r.path, ".bval");
  in.bvec = gradientSibling(r.path, ".bvec");
  if (!fs::exists(in.bval) || !fs::exists(in.bvec))
    throw InputError(r.path + ": a 4D volume with " + std::to_string(h.dims[3]) +
                     " volumes is not a tensor file; as a DWI it needs --bval and --bvec (no " + in.bval +
                     ")");
  in.reason = "4D with " + std::to_string(h.dims[3]) + " volumes (not 6, not SYMMATRIX): a DWI with " +
              in.bval + " and " + in.bvec;
  return in;
}

} // namespace

const char* inputKindName(InputKind kind) {
  static const char* const kNames[] = {"tensor volume", "fibre set", "DWI", "tractogram"}; // InputKind order
  return kNames[static_cast<int>(kind)];
}

std::string gradientSibling(const std::string& path, const std::string& ext) {
  std::string base = path;
  for (const char* suffix : {".nii.gz", ".nii", ".mif.gz", ".mif", ".mih", ".nrrd", ".nhdr"}) {
    std::string s(suffix);
    if (base.size() > s.size() && base.compare(base.size() - s.size(), s.size(), s) == 0) {
      base.resize(base.size() - s.size());
      break;
    }
  }
  return base + ext;
}

std::optional<OpenedInput> openFibreSet(const InputRequest& r, const FormatGuess& g) {
  if (!r.fibres) return std::nullopt;
  if (isFibreLayoutName(r.layout)) {
    OpenedInput in = opened(r, InputKind::Fibres, "fibre layout " + r.layout + " given", g);
    in.fibreLayout = parseFibreLayout(r.layout);
    return in;
  }
  // Gradient files given: a DWI, whatever its values look like.
  if (!r.bval.empty() || !r.bvec.empty()) return std::nullopt;
  std::string why;
  if (r.layout != "auto" || !looksLikeFibres(r.path, g, &why)) return std::nullopt;
  return opened(r, InputKind::Fibres, why, g);
}

OpenedInput openInput(const InputRequest& r) {
  if (r.tractograms && isTractogramName(r.path)) {
    FormatGuess byName;
    byName.reason = "name ends in a tract file extension";
    return opened(r, InputKind::Tractogram, byName.reason, byName);
  }
  const FormatGuess g = detectFormat(r.path);
  if (auto fibres = openFibreSet(r, g)) return *fibres;
  OpenedInput out;
  // A fibre layout where fibre sets are not an answer leaves the tensor layout to detection.
  const TensorLayout layout = isFibreLayoutName(r.layout) ? TensorLayout::Auto : parseLayout(r.layout);
  if (!r.bval.empty() || !r.bvec.empty()) {
    if (r.bval.empty() || r.bvec.empty()) throw UsageError("a DWI needs both --bval and --bvec");
    out = opened(r, InputKind::Dwi, "gradient files given", g);
    out.bval = r.bval;
    out.bvec = r.bvec;
    return out;
  }
  // A dtifit set (basename or member) is a tensor; a DWI with its own gradient table needs no files.
  if (!dtifitSetOf(r.path).empty()) {
    out = opened(r, InputKind::Tensors, "an FSL dtifit set", g);
    out.tensorLayout = layout;
    return out;
  }
  if (hasEmbeddedGradients(r.path, g)) {
    out = opened(r, InputKind::Dwi,
                 std::string("a DWI with its own gradient table (") + formatName(g.format) + ")", g);
    out.embeddedGradients = true;
    return out;
  }
  const VolumeHeader h = readHeader(r.path, g);
  // 9, 12, ... volumes like peaks (6 volumes are refused by the tensor reader itself).
  // Asked already when fibres are an answer and the layout is auto.
  std::string why;
  const bool fibresAsked = r.fibres && r.layout == "auto";
  if (!fibresAsked && h.dims.size() == 4 && h.dims[3] >= 9 && h.dims[3] % 3 == 0 && h.dims[3] <= 48 &&
      looksLikeFibres(r.path, g, &why))
    throw InputError(r.path + ": a fibre set (" + why +
                     "), not a tensor or DWI; `dtfabric render` and `info` read fibre sets");
  if (h.dims.size() == 4 && h.dims[3] > 1 && h.dims[3] != 6 && h.intentCode != 1005)
    return openBySiblings(r, g, h);
  out = opened(r, InputKind::Tensors, "a tensor volume (" + g.reason + ")", g);
  out.tensorLayout = layout;
  return out;
}

namespace {

[[noreturn]] void wrongKind(const OpenedInput& in, const char* wanted) {
  throw InputError(in.path + ": a " + inputKindName(in.kind) + " (" + in.reason + "), not a " + wanted);
}

} // namespace

LoadedTensors readInputTensors(const OpenedInput& in) {
  if (in.kind != InputKind::Tensors) wrongKind(in, "tensor volume");
  return readTensorVolume(in.path, in.format, in.tensorLayout);
}

Dwi readInputDwi(const OpenedInput& in, double b0Threshold) {
  if (in.kind != InputKind::Dwi) wrongKind(in, "DWI");
  return readDwi(in.path, in.format, in.bval, in.bvec, b0Threshold);
}

LoadedFibres readInputFibres(const OpenedInput& in) {
  if (in.kind != InputKind::Fibres) wrongKind(in, "fibre set");
  return readFibres(in.path, in.format, in.fibreLayout);
}

VolumeHeader readInputHeader(const OpenedInput& in) {
  if (in.kind == InputKind::Tractogram) wrongKind(in, "volume");
  return readHeader(in.path, in.format);
}

} // namespace dtf::io
