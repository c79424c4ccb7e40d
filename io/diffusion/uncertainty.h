// SPDX-License-Identifier: GPL-3.0-or-later
// Uncertainty of the principal diffusion direction, beside the tensor fit of io/diffusion/dwi.h: the wild
// bootstrap of the fit (Whitcher et al., HBM 2008) and FSL bedpostx direction samples, each summarised per
// voxel as the 95 % cone of uncertainty (Jones 2003): the 95th percentile of the angle between every sample's
// direction and the samples' dyadic mean (the principal eigenvector of the mean of d d^T). Angles are in
// degrees; directions have no sign, so an angle lies in [0, 90].
#pragma once

#include "io/diffusion/dwi.h"
#include "io/model/volume.h"

#include <cstdint>
#include <string>
#include <vector>

namespace dtf::io {

// Summary of a set of direction samples.
struct DirectionSpread {
  glm::dvec3 mean{0.0}; // dyadic mean, unit (zero when no sample has a length)
  double coneDeg = 0;   // the `percentile`th percentile of the angles to `mean`, degrees
  int samples = 0;      // samples with a non-zero length
};

// The dyadic mean and cone of `count` directions (any length; zero-length and non-finite ones are skipped).
// The percentile is the sample at rank ceil(p/100 * n) of the sorted angles (no interpolation).
DirectionSpread directionSpread(const glm::vec3* directions, std::size_t count, double percentile = 95.0);

struct BootstrapOptions {
  int resamples = 200;      // N refits
  std::uint64_t seed = 1;   // of the Rademacher signs (fixed: the same command gives the same maps)
  double percentile = 95.0; // of the cone
};

// Per-voxel maps on the DWI grid, NaN outside the mask and where the fit is invalid.
struct UncertaintyMaps {
  ScalarVolume cone; // degrees, the cone of uncertainty of the principal eigenvector
  ScalarVolume faSd; // standard deviation of FA over the resamples
};

// Wild bootstrap of the tensor fit: fits as fitTensors (same mask rule, OLS or WLS; the returned field is
// the same fit), then per voxel keeps the fit's weights W and hat matrix H = (X^T W X)^-1 X^T W, forms the
// log-signal residuals r_i scaled by 1/sqrt(1 - h_ii) (leverage), and refits N times from
// y* = y_hat + t_i r_i with Rademacher signs t_i = +-1 (the same N sign vectors in every voxel: the voxels'
// maps are each a valid bootstrap; samples of neighbouring voxels are not independent). Threads and
// progress as fitTensors (progress covers the whole job). Throws as fitTensors, and InputError for
// fewer than 2 resamples or a percentile outside (0, 100).
TensorField bootstrapTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                             const BootstrapOptions& bootstrap, UncertaintyMaps& maps,
                             const ProgressFn& progress = {}, FitStats* stats = nullptr);

// FSL bedpostx direction samples read as cones: per population N = 1, 2, ... the files
// merged_thNsamples, merged_phNsamples (theta, phi per sample, FSL voxel frame: d = (sin t cos p,
// sin t sin p, cos t), x negated when det(affine) > 0) and merged_fNsamples (volume fractions), 4D with one
// volume per sample.
struct BedpostxSamples {
  Grid grid;
  std::vector<ScalarVolume> cone;  // per population: degrees; NaN where mean f < minFraction
  std::vector<Volume<float>> mean; // per population: dyadic mean direction, world RAS, 3 components
  std::vector<ScalarVolume> meanFraction;
  std::vector<std::string> files; // the files read
  int samples = 0;
};
// `path` is a bedpostx folder or one of its merged_* files. Throws InputError naming the file for a
// missing population-1 file, differing grids or sample counts, or non-finite angles inside the data.
BedpostxSamples readBedpostxSamples(const std::string& path, double percentile = 95.0,
                                    double minFraction = 0.05);
// True for a folder holding merged_th1samples.nii[.gz] or for one of the merged_*samples files.
bool isBedpostxSamplesPath(const std::string& path);

// A cone map for display: a scalar NIfTI of degrees (3D), or a bedpostx folder / merged_* file (its
// population-1 cone). Throws InputError naming the file for a 4D volume or values outside [0, 90] + NaN.
ScalarVolume readConeMap(const std::string& path);

} // namespace dtf::io
