// The tracking session behind `dtfabric track` and dtfabric.track (Python).
#include "ui/session/track_job.h"

#include "io/model/error.h"
#include "surfaces/slices.h"

#include <chrono>

namespace dtf::session {

MaskVolume loadMaskVolume(const std::string& path) {
  ScalarVolume m = io::readScalarVolume(path);
  MaskVolume out(m.grid, 1);
  for (std::size_t i = 0; i < m.grid.voxelCount(); ++i)
    out.data[i] = m.data[i * m.components] > 0 ? 1 : 0;
  return out;
}

TrackRun runTrack(const TrackRequest& r) {
  const int seedKinds = !r.seedsMask.empty() + r.seedSphere.has_value() + r.seedSurface.has_value() +
                        r.seedSliceAxis.has_value();
  if (seedKinds > 1)
    throw UsageError("give at most one of --seeds-mask, --seed-sphere, --seed-surface, --seed-slice");
  if (r.seedsPerVoxel < 0 || (r.seedsPerVoxel > 0 && r.seedsMask.empty()))
    throw UsageError("--seeds-per-voxel K needs --seeds-mask and K >= 0");
  if (r.seedCount < 0) throw UsageError("--seeds must be positive");
  if (r.seedCount == 0 && r.seedsPerVoxel == 0 && r.select <= 0)
    throw UsageError("--select must be positive");
  surfaces::TrackingOptions to = r.options;
  surfaces::validate(to);

  io::LoadedTensors loaded;
  if (!r.field) loaded = loadTensorInput(r.input, r.tensorOptions);
  const TensorField& field = r.field ? *r.field : loaded.field;

  MaskVolume stop;
  if (!r.stopMask.empty()) {
    stop = loadMaskVolume(r.stopMask);
    to.mask = &stop;
  }
  const std::uint64_t seed = r.rngSeed;
  surfaces::SeedSource source;
  if (!r.seedsMask.empty()) {
    source = surfaces::seedsFromMask(loadMaskVolume(r.seedsMask), r.seedsPerVoxel, seed);
  } else if (r.seedSphere) {
    const glm::dvec4& s = *r.seedSphere;
    source = surfaces::seedsInSphere(glm::dvec3(s), s.w, seed);
  } else if (r.seedSurface) {
    Mesh mesh;
    try {
      mesh = buildSurface(*r.seedSurface, field, computeFaMap(field));
    } catch (const Error&) {
      rethrowWithContext("while building the seed surface " + describeSurface(*r.seedSurface));
    }
    source = surfaces::seedsOnSurface(mesh, seed);
  } else if (r.seedSliceAxis) {
    const surfaces::SliceAxis axis = surfaces::parseSliceAxis(*r.seedSliceAxis);
    source = surfaces::seedsOnSlice(field, surfaces::voxelAxisFor(field.grid, axis), r.seedSliceIndex,
                                    to.mask, seed);
  } else {
    MaskVolume valid(field.grid, 1);
    valid.data = field.valid;
    source = surfaces::seedsFromMask(valid, 0, seed);
    source.description += " (where INPUT holds a tensor)";
  }

  TrackRun run;
  run.grid = field.grid;
  run.seedDescription = source.description;
  const auto t0 = std::chrono::steady_clock::now();
  if (r.seedsPerVoxel > 0) {
    run.result = surfaces::trackSeeds(field, source, source.count, to);
    run.mode = std::to_string(source.count) + " seeds";
  } else if (r.seedCount > 0) {
    run.result = surfaces::trackSeeds(field, source, static_cast<std::uint64_t>(r.seedCount), to);
    run.mode = std::to_string(r.seedCount) + " seeds";
  } else {
    run.result = surfaces::trackSelect(field, source, static_cast<std::size_t>(r.select), to);
    run.mode = "select " + std::to_string(r.select);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

} // namespace dtf::session
