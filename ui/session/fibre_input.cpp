#include "ui/session/fibre_input.h"

#include "io/model/error.h"
#include "io/model/log.h"
#include "io/model/tensor.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace dtf::session {

bool isFibreInput(const std::string& path, const std::string& layoutText, bool quiet) {
  if (io::isFibreLayoutName(layoutText)) return true;
  if (layoutText != "auto") return false;
  std::string reason;
  const bool yes = io::looksLikeFibres(path, &reason);
  if (yes && !quiet) logInfo(path + ": read as a fibre set (" + reason + ")");
  return yes;
}

FibreInput loadFibreInput(const std::string& path, const std::string& layoutText,
                          const std::string& tensorPath, bool quiet) {
  FibreInput in;
  in.fibres = io::readFibres(path, io::parseFibreLayout(layoutText == "auto" ? "auto" : layoutText));
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

namespace {
std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}
std::string vec(const glm::dvec3& v) {
  return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]";
}
} // namespace

int describeFibreInput(const std::string& path, const std::string& layoutText, const std::string& tensorPath,
                       const int* ijk, bool json) {
  FibreInput in = loadFibreInput(path, layoutText, tensorPath, true);
  const FibreSet& s = in.fibres.set;
  const Grid& g = s.grid;
  const std::string layout = io::fibreLayoutName(in.fibres.layout);
  if (!ijk) {
    if (json) {
      std::printf("{\"file\":\"%s\",\"is_tensor\":false,\"is_fibres\":true,\"fibre_layout\":\"%s\","
                  "\"layout_reason\":\"%s\",\"dims\":[%d,%d,%d],\"orientation\":\"%s\",\"max_fibres\":%d,"
                  "\"voxels_with_fibres\":%zu,\"max_amplitude\":%s}\n",
                  path.c_str(), layout.c_str(), in.fibres.layoutReason.c_str(), g.dims.x, g.dims.y, g.dims.z,
                  g.orientationCode().c_str(), s.maxFibres, s.occupiedVoxels(),
                  num(s.maxAmplitude()).c_str());
      return 0;
    }
    std::printf("file:         %s\n", path.c_str());
    std::printf("fibre set:    %s (%s)\n", layout.c_str(), in.fibres.layoutReason.c_str());
    std::printf("dims:         %d x %d x %d, %s, up to %d fibres per voxel\n", g.dims.x, g.dims.y, g.dims.z,
                g.orientationCode().c_str(), s.maxFibres);
    std::printf("voxels:       %zu with fibres; largest amplitude %s\n", s.occupiedVoxels(),
                num(s.maxAmplitude()).c_str());
    for (const std::string& w : in.fibres.warnings)
      std::printf("warning:      %s\n", w.c_str());
    return 0;
  }
  if (!g.contains(ijk[0], ijk[1], ijk[2]))
    throw UsageError("voxel " + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                     std::to_string(ijk[2]) + " is outside the grid " + std::to_string(g.dims.x) + "x" +
                     std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z));
  const glm::dvec3 world = g.toWorld(glm::dvec3(ijk[0], ijk[1], ijk[2]));
  const Fibre* f = s.at(ijk[0], ijk[1], ijk[2]);
  const int n = s.count(g.index(ijk[0], ijk[1], ijk[2]));
  std::string tensorJson, tensorText;
  if (in.tensor) {
    const std::size_t idx = g.index(ijk[0], ijk[1], ijk[2]);
    const EigenSystem e = eigenDecompose(in.tensor->field.tensors[idx].toMat());
    const double fa = in.tensor->field.valid[idx] ? computeMetrics(e).fa : 0.0;
    tensorJson = ", \"is_tensor\": true, \"tensor_file\": \"" + tensorPath +
                 "\", \"valid\": " + (in.tensor->field.valid[idx] ? "true" : "false") +
                 ", \"fa\": " + num(fa) + ", \"eigenvalues\": " + vec(e.values) + ", \"eigenvectors\": [" +
                 vec(e.vectors[0]) + ", " + vec(e.vectors[1]) + ", " + vec(e.vectors[2]) + "]";
    tensorText = "tensor:       " + tensorPath + ": FA " + num(fa) + ", e1 " + vec(e.vectors[0]) + "\n";
  } else {
    tensorJson = ", \"is_tensor\": false";
    if (!in.fa.data.empty()) {
      const double fa = in.fa.data[g.index(ijk[0], ijk[1], ijk[2])];
      tensorJson += ", \"fa\": " + num(fa) + ", \"fa_file\": \"" + in.faSource + "\"";
      tensorText = "FA:           " + num(fa) + " (" + in.faSource + ")\n";
    }
  }
  if (json) {
    std::string fibres;
    for (int k = 0; k < n; ++k)
      fibres += std::string(k ? ", " : "") + "{\"direction\": " + vec(glm::dvec3(f[k].direction)) +
                ", \"amplitude\": " + num(f[k].amplitude) + "}";
    std::printf("{\"file\": \"%s\", \"voxel\": [%d, %d, %d], \"world\": %s, \"is_fibres\": true, "
                "\"fibre_layout\": \"%s\", \"fibres\": [%s]%s}\n",
                path.c_str(), ijk[0], ijk[1], ijk[2], vec(world).c_str(), layout.c_str(), fibres.c_str(),
                tensorJson.c_str());
    return 0;
  }
  std::printf("file:         %s\n", path.c_str());
  std::printf("voxel:        %d, %d, %d\n", ijk[0], ijk[1], ijk[2]);
  std::printf("world:        %s mm (RAS)\n", vec(world).c_str());
  std::printf("fibre layout: %s\n", layout.c_str());
  if (n == 0) std::printf("note:         no fibre in this voxel\n");
  for (int k = 0; k < n; ++k)
    std::printf("fibre %d:      direction %8.5f %8.5f %8.5f (unit, world RAS), amplitude %s\n", k + 1,
                f[k].direction.x, f[k].direction.y, f[k].direction.z, num(f[k].amplitude).c_str());
  std::fputs(tensorText.c_str(), stdout);
  return 0;
}

} // namespace dtf::session
