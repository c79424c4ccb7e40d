// SPDX-License-Identifier: GPL-3.0-or-later
// The tracking session behind `dtfabric track`, dtfabric.track (Python) and the viewer's tract worker.
#include "ui/session/track_job.h"

#include "surfaces/selection/tract_selection.h"

#include "io/model/error.h"
#include "surfaces/slices.h"

#include <chrono>
#include <cstdio>
#include <memory>

namespace dtf::session {

MaskVolume loadMaskVolume(const std::string& path) {
  ScalarVolume m = io::readScalarVolume(path);
  MaskVolume out(m.grid, 1);
  for (std::size_t i = 0; i < m.grid.voxelCount(); ++i)
    out.data[i] = m.data[i * m.components] > 0 ? 1 : 0;
  return out;
}

void validate(const TrackRequest& r) {
  surfaces::validate(r.options);
  if (r.number < 1)
    throw UsageError(r.count == SeedCount::Select  ? "the number of streamlines to select must be positive"
                     : r.count == SeedCount::Seeds ? "the number of seeds must be positive"
                                                   : "seeds per voxel must be positive");
  const int most = r.count == SeedCount::Select  ? kMaxSelect
                   : r.count == SeedCount::Seeds ? kMaxSeeds
                                                 : kMaxSeedsPerVoxel;
  if (r.number > most)
    throw UsageError(std::string(r.count == SeedCount::Select  ? "the number of streamlines to select"
                                 : r.count == SeedCount::Seeds ? "the number of seeds"
                                                               : "seeds per voxel") +
                     " may be at most " + std::to_string(most) + " (asked for " + std::to_string(r.number) +
                     ")");
  if (r.count == SeedCount::PerVoxel && r.seeds != SeedKind::Mask && r.seeds != SeedKind::FaMask)
    throw UsageError("seeds per voxel need mask seeds (a seed mask or an FA mask)");
  if (r.seeds == SeedKind::Mask && r.seedsMask.empty()) throw UsageError("mask seeds need a seed mask file");
  if (r.seeds == SeedKind::Slice && (r.sliceAxis < 0 || r.sliceAxis > 2))
    throw UsageError("the seed slice axis must be axial, coronal or sagittal");
  if (r.seeds == SeedKind::Sphere && !(r.radiusMm > 0 && r.radiusMm <= 1000))
    throw UsageError("the seed sphere radius must lie in (0, 1000] mm");
  if (r.seeds == SeedKind::FaMask && !(r.faMask > 0 && r.faMask < 1))
    throw UsageError("the seed FA threshold must lie in (0, 1)");
}

surfaces::SeedSource seedsFor(const TrackRequest& r, const TensorField& field, const ScalarVolume* fa,
                              const Mesh* surfaceOnScreen, const MaskVolume* stop) {
  const std::uint64_t seed = r.rngSeed;
  const int perVoxel = r.count == SeedCount::PerVoxel ? r.number : 0;
  switch (r.seeds) {
  case SeedKind::Data: {
    MaskVolume valid(field.grid, 1);
    valid.data = field.valid;
    surfaces::SeedSource s = surfaces::seedsFromMask(valid, 0, seed);
    s.description += " (where the input holds a tensor)";
    return s;
  }
  case SeedKind::Mask:
    return surfaces::seedsFromMask(loadMaskVolume(r.seedsMask), perVoxel, seed);
  case SeedKind::Surface: {
    if (!r.seedSurface) {
      if (!surfaceOnScreen || surfaceOnScreen->empty()) throw UsageError("no surface on screen to seed from");
      return surfaces::seedsOnSurface(*surfaceOnScreen, seed);
    }
    Mesh mesh;
    try {
      mesh = buildSurface(*r.seedSurface, field, fa ? *fa : computeFaMap(field));
    } catch (const Error&) {
      rethrowWithContext("while building the seed surface " + describeSurface(*r.seedSurface));
    }
    return surfaces::seedsOnSurface(mesh, seed);
  }
  case SeedKind::Slice: {
    const auto axis = static_cast<surfaces::SliceAxis>(r.sliceAxis);
    return surfaces::seedsOnSlice(field, surfaces::voxelAxisFor(field.grid, axis), r.sliceIndex, stop, seed);
  }
  case SeedKind::Sphere:
    return surfaces::seedsInSphere(r.centre, r.radiusMm, seed);
  case SeedKind::FaMask: {
    const ScalarVolume own = fa ? ScalarVolume{} : computeFaMap(field);
    const ScalarVolume& f = fa ? *fa : own;
    MaskVolume mask(f.grid, 1);
    for (std::size_t i = 0; i < f.grid.voxelCount(); ++i)
      mask.data[i] = f.data[i * static_cast<std::size_t>(f.components)] >= r.faMask ? 1 : 0;
    char what[64];
    std::snprintf(what, sizeof what, " (FA >= %g)", r.faMask);
    surfaces::SeedSource s = surfaces::seedsFromMask(mask, perVoxel, seed);
    s.description += what;
    return s;
  }
  }
  throw UsageError("unknown seed kind");
}

TrackRun runTrack(const TrackRequest& r) {
  validate(r);
  surfaces::TrackingOptions to = r.options;

  io::LoadedTensors loaded;
  if (!r.field) loaded = loadTensorInput(r.input, r.tensorOptions);
  const TensorField& field = r.field ? *r.field : loaded.field;

  MaskVolume stop;
  if (!r.stopMask.empty()) {
    stop = loadMaskVolume(r.stopMask);
    to.mask = &stop;
  }
  const surfaces::SeedSource source = seedsFor(r, field, nullptr, nullptr, to.mask);
  if (r.regions.hasRegions() || r.regions.hasLengthRange()) {
    auto tester = std::make_shared<const surfaces::RegionTester>(r.regions);
    to.accept = [tester](const glm::vec3* p, std::size_t n) { return tester->accepts(p, n); };
  }

  TrackRun run;
  run.grid = field.grid;
  run.seedDescription = source.description;
  const auto t0 = std::chrono::steady_clock::now();
  if (r.count == SeedCount::PerVoxel) {
    run.result = surfaces::trackSeeds(field, source, source.count, to);
    run.mode = std::to_string(source.count) + " seeds";
  } else if (r.count == SeedCount::Seeds) {
    run.result = surfaces::trackSeeds(field, source, static_cast<std::uint64_t>(r.number), to);
    run.mode = std::to_string(r.number) + " seeds";
  } else {
    run.result = surfaces::trackSelect(field, source, static_cast<std::size_t>(r.number), to);
    run.mode = "select " + std::to_string(r.number);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

} // namespace dtf::session
