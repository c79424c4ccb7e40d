#include "ui/session/tensor_input.h"

#include "io/diffusion/dwi.h"
#include "io/formats/formats.h"
#include "io/formats/fibre_io.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <filesystem>

namespace fs = std::filesystem;

namespace dtf::session {

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

io::LoadedTensors loadTensorInput(const std::string& path, const TensorInputOptions& o) {
  std::string bval = o.bval, bvec = o.bvec;
  bool dwi = !bval.empty() || !bvec.empty();
  // A dtifit set (basename or member) is a tensor; a DWI with its own gradient table needs no files.
  if (!dwi && !io::dtifitSetOf(path).empty()) return io::readTensorVolume(path, o.layout);
  const bool embedded = !dwi && io::hasEmbeddedGradients(path);
  if (!dwi && !embedded) {
    io::VolumeHeader h = io::readHeader(path);
    // 9, 12, ... volumes signed like directions: peaks (6 volumes are refused by the tensor reader itself).
    std::string why;
    if (h.dims.size() == 4 && h.dims[3] >= 9 && h.dims[3] % 3 == 0 && h.dims[3] <= 48 &&
        io::looksLikeFibres(path, &why))
      throw InputError(path + ": a fibre set (" + why +
                       "), not a tensor or DWI; `dtfabric render` and `info` "
                       "read fibre sets");
    const bool fourD = h.dims.size() == 4 && h.dims[3] > 1;
    if (fourD && h.dims[3] != 6 && h.intentCode != 1005) {
      dwi = true;
      bval = gradientSibling(path, ".bval");
      bvec = gradientSibling(path, ".bvec");
      if (!fs::exists(bval) || !fs::exists(bvec))
        throw InputError(path + ": a 4D volume with " + std::to_string(h.dims[3]) +
                         " volumes is not a tensor file; as a DWI it needs --bval and --bvec (no " + bval +
                         ")");
    }
  }
  if (!dwi && !embedded) return io::readTensorVolume(path, o.layout);
  if (!embedded && (bval.empty() || bvec.empty())) throw UsageError("a DWI needs both --bval and --bvec");
  io::Dwi d = io::readDwi(path, bval, bvec);
  MaskVolume mask;
  if (!o.mask.empty()) {
    ScalarVolume m = io::readScalarVolume(o.mask);
    if (m.grid.dims != d.signal.grid.dims)
      throw InputError(o.mask + ": mask grid differs from the DWI " + path);
    mask = MaskVolume(m.grid, 1);
    for (std::size_t i = 0; i < m.grid.voxelCount(); ++i)
      mask.data[i] = m.data[i * m.components] > 0 ? 1 : 0;
  }
  if (!o.quiet)
    logInfo("fitting tensors to " + path + " (WLS" + (o.mask.empty() ? ", automatic mask)" : ")"));
  io::LoadedTensors out;
  io::FitOptions fo;
  io::ProgressFn progress;
  if (o.onStage)
    progress = [&](double f) {
      o.onStage("fitting tensors to " + path + ": " + std::to_string(static_cast<int>(100 * f)) + "%");
    };
  out.field = io::fitTensors(d, o.mask.empty() ? nullptr : &mask, fo, progress);
  out.layout = io::TensorLayout::Auto;
  out.layoutReason = "fitted from the DWI " + path +
                     (embedded ? " with its own gradient table" : " with " + bval + " and " + bvec);
  out.header = io::readHeader(path);
  return out;
}

} // namespace dtf::session
