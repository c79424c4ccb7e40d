// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/fibre_input.h"

#include "io/model/error.h"
#include "io/model/log.h"
#include "io/model/tensor.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace dtf::session {

bool isFibreSet(const std::string& path, const std::string& layoutText) {
  io::InputRequest r;
  r.path = path;
  r.layout = layoutText;
  return io::openFibreSet(r, io::detectFormat(path)).has_value();
}

FibreInput loadFibreInput(const std::string& path, const std::string& layoutText,
                          const std::string& tensorPath, bool quiet) {
  io::InputRequest r;
  r.path = path;
  r.layout = layoutText == "auto" ? "fibres-auto" : layoutText;
  io::parseFibreLayout(r.layout); // UsageError for a name that is not a fibre layout
  return loadFibreInput(io::openInput(r), tensorPath, quiet);
}

FibreInput loadFibreInput(const io::OpenedInput& input, const std::string& tensorPath, bool quiet) {
  const std::string& path = input.path;
  FibreInput in;
  in.fibres = io::readInputFibres(input);
  if (!quiet) {
    logInfo(path + ": fibre layout " + io::fibreLayoutName(in.fibres.layout) + " (" + in.fibres.layoutReason +
            ")");
    for (const std::string& w : in.fibres.warnings)
      logWarning(path + ": " + w);
  }
  if (!tensorPath.empty()) {
    in.tensor = io::readTensorVolume(tensorPath);
    if (in.tensor->field.grid.dims != in.fibres.set.grid.dims)
      throw InputError(tensorPath + ": its grid differs from the fibre set " + path);
    in.carrier = in.tensor->field;
    in.fa = computeFaMap(in.carrier);
    in.faSource = tensorPath;
  } else {
    in.carrier = fibreCarrierField(in.fibres.set);
    if (!in.fibres.fa.data.empty()) {
      in.fa = in.fibres.fa;
      in.faSource = in.fibres.files.back();
      if (!quiet) logInfo(path + ": FA from " + in.faSource + " (the fibre file's own)");
    }
  }
  return in;
}

namespace {
bool needsKind(const SurfaceSpec& s, SurfaceSpec::Kind kind) {
  if (s.kind == kind) return true;
  for (const SurfaceSpec& p : s.parts)
    if (needsKind(p, kind)) return true;
  return false;
}
} // namespace

void checkFibreSurface(const SurfaceSpec& spec, const FibreInput& input) {
  if ((!input.tensor && needsKind(spec, SurfaceSpec::Kind::Fibre)) ||
      (input.fa.data.empty() && needsKind(spec, SurfaceSpec::Kind::Fa)))
    throw UsageError("the surface " + describeSurface(spec) +
                     " needs FA or tensor directions, which a fibre set does not have: pair a tensor with "
                     "--tensor FILE, or use a slice, plane, iso=FILE:V or mesh surface");
}

FibreSet principalFibres(const TensorField& field) {
  FibreSet s = makeFibreSet(field.grid, 1);
  for (std::size_t i = 0; i < field.tensors.size(); ++i) {
    if (!field.valid[i]) continue;
    const EigenSystem e = eigenDecompose(field.tensors[i].toMat());
    const double fa = computeMetrics(e).fa;
    if (!(fa > 0) || !std::isfinite(fa)) continue;
    s.fibres[i] = {glm::vec3(glm::normalize(e.vectors[0])), static_cast<float>(fa)};
  }
  return s;
}

UncertaintyMap readUncertainty(const std::string& path) {
  UncertaintyMap m;
  if (io::isBedpostxSamplesPath(path)) {
    auto samples = std::make_shared<io::BedpostxSamples>(io::readBedpostxSamples(path));
    m.cone = samples->cone.at(0);
    m.samples = std::move(samples);
  } else {
    m.cone = io::readConeMap(path);
  }
  return m;
}

ScalarVolume conesFor(const UncertaintyMap& map, const FibreSet* fibres) {
  if (!fibres || !map.samples || map.samples->grid.dims != fibres->grid.dims || fibres->maxFibres < 1)
    return map.cone;
  const io::BedpostxSamples& s = *map.samples;
  const std::size_t k = static_cast<std::size_t>(fibres->maxFibres);
  ScalarVolume out(fibres->grid, fibres->maxFibres);
  for (std::size_t v = 0; v < fibres->grid.voxelCount(); ++v)
    for (std::size_t i = 0; i < k; ++i) {
      const Fibre& f = fibres->fibres[v * k + i];
      float best = -1.0f, cone = std::nanf("");
      for (std::size_t p = 0; p < s.cone.size(); ++p) {
        const float c = s.cone[p].data[v];
        const glm::vec3 m(s.mean[p].data[v * 3], s.mean[p].data[v * 3 + 1], s.mean[p].data[v * 3 + 2]);
        const float cosine = std::abs(glm::dot(m, f.direction));
        if (f.amplitude > 0.0f && cosine > best) {
          best = cosine;
          cone = c;
        }
      }
      out.data[v * k + i] = cone;
    }
  return out;
}

} // namespace dtf::session
