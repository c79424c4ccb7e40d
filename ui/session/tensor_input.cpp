// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tensor_input.h"

#include "io/model/error.h"
#include "io/model/log.h"

#include <algorithm>

namespace dtf::session {

io::InputRequest inputRequest(const std::string& path, const std::string& layoutText,
                              const TensorInputOptions& o, bool fibres) {
  io::InputRequest r;
  r.path = path;
  r.layout = layoutText;
  r.bval = o.bval;
  r.bvec = o.bvec;
  r.fibres = fibres;
  return r;
}

ScalarVolume meanLowestB(const io::Dwi& d) {
  const int n = d.signal.components;
  if (n < 1 || d.bvals.size() != static_cast<std::size_t>(n)) return {};
  const double lowest = *std::min_element(d.bvals.begin(), d.bvals.end());
  std::vector<int> use;
  for (int v = 0; v < n; ++v)
    if (d.bvals[static_cast<std::size_t>(v)] <= lowest + 50.0) use.push_back(v);
  ScalarVolume out(d.signal.grid, 1);
  for (std::size_t i = 0; i < d.signal.grid.voxelCount(); ++i) {
    double sum = 0;
    for (int v : use)
      sum += d.signal.data[i * static_cast<std::size_t>(n) + static_cast<std::size_t>(v)];
    out.data[i] = static_cast<float>(sum / static_cast<double>(use.size()));
  }
  return out;
}

io::LoadedTensors loadTensorInput(const std::string& path, const TensorInputOptions& o) {
  return loadTensors(io::openInput(inputRequest(path, io::layoutName(o.layout), o, false)), o);
}

io::LoadedTensors loadTensors(const io::OpenedInput& in, const TensorInputOptions& o) {
  if (in.kind == io::InputKind::Tensors) return io::readTensorVolume(in.path, in.format, o.layout);
  if (in.kind != io::InputKind::Dwi)
    throw InputError(in.path + ": a " + io::inputKindName(in.kind) + " (" + in.reason +
                     "), not a tensor volume or DWI");
  const io::Dwi d = io::readInputDwi(in);
  const std::string& path = in.path;
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
  out.layoutReason =
      "fitted from the DWI " + path +
      (in.embeddedGradients ? " with its own gradient table" : " with " + in.bval + " and " + in.bvec);
  out.header = io::readInputHeader(in);
  out.meanB0 = meanLowestB(d);
  return out;
}

} // namespace dtf::session
