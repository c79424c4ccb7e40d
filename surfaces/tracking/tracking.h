// SPDX-License-Identifier: GPL-3.0-or-later
// Deterministic tensor tractography: streamlines along the principal eigenvector e1 of the trilinearly
// interpolated tensor (components interpolated, never eigenvectors), the comparison layer beside the
// fabric. Input is a canonical TensorField (world RAS); output Polylines in world
// RAS mm, ready for io/formats/tracts.h, surfaces/polyline_io.h and the agreement measure in surfaces/analyses/agreement.h.
//
// Integration: from each seed, e1 is followed in both directions with RK4 (or Euler) steps of stepMm,
// the sign of e1 kept continuous with the previous step. A direction stops when the FA of the
// interpolated tensor at the new point falls below faStop, the point leaves the data (zero tensor) or the
// stop mask, the step direction turns by more than maxAngleDeg from the previous step (per step, as
// MRtrix's -angle; with the default 1 mm step 60 degrees per step allows a radius of curvature down to
// 1 mm, so in practice FA and the mask end streamlines), or the streamline reaches maxLengthMm. Seeds
// below faStop are rejected, as are streamlines shorter than minLengthMm.
//
// Seeds are a function of their index (counter-based random numbers from a fixed seed), and each
// streamline depends only on its seed, so the output is the same for any thread count: seed i fills
// slot i, and accepted streamlines are emitted in seed order.
#pragma once

#include "io/model/geometry.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dtf::surfaces {

// The tracking parameters a user sets; their names, help and ranges are in tracking_parameters.h.
struct TrackingParams {
  double stepMm = 1.0;       // step length (the reference tracks use 1 mm; MRtrix's default is 0.1 voxel)
  double faStop = 0.15;      // stop (and reject seeds) below this FA
  double maxAngleDeg = 60.0; // largest turn between successive steps
  double minLengthMm = 30.0; // shorter streamlines are discarded
  double maxLengthMm = 250.0;
  bool rk4 = true; // false: Euler (MRtrix Tensor_Det's default)
};

// The parameters and how one run goes: its stop mask, threads, progress and cancellation.
struct TrackingOptions : TrackingParams {
  TrackingOptions() = default;
  explicit TrackingOptions(const TrackingParams& p) : TrackingParams(p) {}
  const MaskVolume* mask = nullptr; // stop where the nearest voxel of this mask is 0 (any grid); optional
  int threads = 0;                  // 0 = all hardware threads
  // Called on the calling thread about every 100 ms with (seeds done, seeds planned so far).
  std::function<void(std::size_t, std::size_t)> progress;
  const std::atomic<bool>* cancel = nullptr; // set to stop early; the result then has cancelled = true
  // Targeted tracking: a streamline this refuses (called from worker threads, after the length check) is not
  // kept and counts as rejectedByRegions, as tckgen's -include/-exclude; --select keeps seeding past them.
  std::function<bool(const glm::vec3* points, std::size_t n)> accept;
};

// A deterministic seed generator: position (world RAS mm) of seed i. `count` is the natural number of
// seeds (e.g. voxels x per-voxel count), 0 when the source is unbounded (random draws).
struct SeedSource {
  std::function<glm::dvec3(std::uint64_t)> at;
  std::uint64_t count = 0;
  std::string description;
};

// `perVoxel` > 0: seeds i*perVoxel .. are jittered uniformly inside mask voxel i (count = voxels x
// perVoxel); perVoxel == 0: each seed picks a random mask voxel and a random point in it (unbounded).
// Throws InputError when the mask is empty.
SeedSource seedsFromMask(const MaskVolume& mask, int perVoxel, std::uint64_t rngSeed);
// Uniform random points in a ball (world mm). Throws UsageError for a non-positive radius.
SeedSource seedsInSphere(const glm::dvec3& centre, double radiusMm, std::uint64_t rngSeed);
// Area-weighted random points on a mesh's triangles. Throws InputError for a mesh without area.
SeedSource seedsOnSurface(const Mesh& mesh, std::uint64_t rngSeed);
// Random points in the voxels of slice `index` along voxel axis `axis` (0 = i, 1 = j, 2 = k) that are valid
// in `field` (and inside `mask` when given), jittered within the slice plane. Throws InputError when the
// index is outside the grid or the slice holds no valid voxel.
SeedSource seedsOnSlice(const TensorField& field, int axis, int index, const MaskVolume* mask,
                        std::uint64_t rngSeed);

struct TrackingResult {
  Polylines lines;
  std::vector<std::uint64_t> seedIndex; // per streamline, the seed it grew from
  std::size_t seedsTried = 0;
  std::size_t seedsBelowFa = 0; // seed rejected: outside the data or FA < faStop
  std::size_t tooShort = 0;     // rejected by minLengthMm
  std::size_t rejectedByRegions = 0; // refused by options.accept
  bool cancelled = false;
  int threads = 1;
};

// Tracks seeds 0 .. seedCount-1 of `seeds`, keeping the streamlines that pass the length limits.
TrackingResult trackSeeds(const TensorField& field, const SeedSource& seeds, std::uint64_t seedCount,
                          const TrackingOptions& options);
// Draws seeds 0, 1, 2 ... until `select` streamlines are accepted (or maxSeeds are tried, 0 = 1000 x
// select, as MRtrix's -select); returns exactly the first `select` accepted, in seed order.
TrackingResult trackSelect(const TensorField& field, const SeedSource& seeds, std::size_t select,
                           const TrackingOptions& options, std::uint64_t maxSeeds = 0);

// One streamline from one seed (both directions joined, seed in the middle); empty when the seed is
// rejected. Exposed for tests and interactive single-seed tracking.
std::vector<glm::vec3> trackOne(const TensorField& field, const glm::dvec3& seed,
                                const TrackingOptions& options);

// Throws UsageError when a parameter lies outside its range in tracking_parameters.h, or min > max length.
void validate(const TrackingParams& params);

} // namespace dtf::surfaces
