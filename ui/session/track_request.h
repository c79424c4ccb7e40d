// SPDX-License-Identifier: GPL-3.0-or-later
// One tractography request, as `dtfabric track`, dtfabric.track (Python), the viewer's Tracking panel and
// its script's `track` line make it: the tensors, where to seed, how many, and the tracking parameters
// (surfaces/tracking/tracking_parameters.h). runTrack (track_job.h) runs it on a file or field; the
// viewer's tract worker on the data and surface on screen. Both build the seeds with seedsFor.
#pragma once

#include "io/model/tensor_field.h"
#include "io/model/volume.h"
#include "surfaces/selection/regions.h"
#include "surfaces/tracking/tracking.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>

namespace dtf::session {

// Where the seeds lie.
enum class SeedKind {
  Data,    // random points in the voxels where the tensors are valid
  Mask,    // random points in the non-zero voxels of `seedsMask` (a NIfTI mask)
  Surface, // area-weighted points on `seedSurface`, or, unset, on the viewer's surface on screen
  Slice,   // random points in the valid voxels of slice `sliceIndex` on `sliceAxis`
  Sphere,  // uniform points in the ball `centre`, `radiusMm`
  FaMask,  // random points in the voxels with FA >= `faMask`
};
// What `number` counts.
enum class SeedCount {
  Select,   // keep seeding until `number` streamlines are accepted
  Seeds,    // track exactly `number` seeds
  PerVoxel, // `number` seeds in every voxel of the mask (Mask, FaMask)
};

struct TrackRequest {
  // The tensors: a tensor file or DWI, or (set) these tensors; the viewer tracks the data it shows.
  std::string input;
  const TensorField* field = nullptr;
  TensorInputOptions tensorOptions;

  SeedKind seeds = SeedKind::Data;
  std::string seedsMask;                  // Mask
  std::optional<SurfaceSpec> seedSurface; // Surface (unset: the surface on screen)
  int sliceAxis = 0;                      // Slice: 0 axial, 1 coronal, 2 sagittal (world axes)
  int sliceIndex = -1;                    // Slice: -1 = the viewer's current slice on that axis
  glm::dvec3 centre{0.0};                 // Sphere: world mm
  double radiusMm = 10.0;
  double faMask = 0.3; // FaMask

  SeedCount count = SeedCount::Select;
  int number = 1000;
  std::uint64_t rngSeed = 1;

  std::string stopMask;              // stop where this NIfTI mask is zero ("" none)
  surfaces::RegionSet regions;       // targeted tracking: keep only the streamlines this set selects
  surfaces::TrackingOptions options; // the parameters, threads, progress; mask is set from stopMask
};

// The largest counts a request may ask for: 10 million accepted streamlines (a whole-brain connectome; about
// 12 GB of points at 100 points each), 100 million seeds, 1000 seeds in every mask voxel.
inline constexpr int kMaxSelect = 10'000'000, kMaxSeeds = 100'000'000, kMaxSeedsPerVoxel = 1000;

// Checks the request's values and combinations (UsageError): the parameters' ranges, a positive number
// (at most the kMax... above), per-voxel counts only with mask seeds, a positive radius, an FA threshold in
// (0, 1).
void validate(const TrackRequest& r);

// The seed generator of a request. `fa` is needed for FaMask seeds, `surfaceOnScreen` for Surface seeds
// without a spec (the viewer), `stop` restricts slice seeds. Builds the spec's surface when one is given.
// Throws UsageError or InputError (an empty mask, a slice outside the grid) naming the problem.
surfaces::SeedSource seedsFor(const TrackRequest& r, const TensorField& field, const ScalarVolume* fa,
                              const Mesh* surfaceOnScreen, const MaskVolume* stop);

} // namespace dtf::session
