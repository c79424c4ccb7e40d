// SPDX-License-Identifier: GPL-3.0-or-later
// Tract profiles (tractometry): a bundle of streamlines measured along its length, as DIPY's `afq_profile`
// and pyAFQ do. The streamlines are oriented alike (to agree with the bundle's first streamline as DIPY's
// `orient_by_streamline` decides it, or to start at the end nearer a given point), resampled to N nodes
// equally spaced by arc length (DIPY `set_number_of_points`), and each scalar image is sampled at every node
// in world space, trilinearly in the image's voxel frame with zero padding as DIPY `values_from_volume`
// does. Per node: a weighted mean over the streamlines (gauss, mean or median), its standard deviation, a
// seeded bootstrap confidence interval over streamlines, the core's position and the streamline count.
// Pure computation on io/model types; reading files, naming bundles and writing tables is ui/session's.
#pragma once

#include "io/model/geometry.h"
#include "io/model/volume.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dtf::surfaces {

enum class ProfileWeights {
  Gauss,  // DIPY gaussian_weights: 1 / Mahalanobis distance from the node's mean, normalised per node
  Mean,   // equal weights
  Median, // the (unweighted) median of the node's values
};

struct ProfileOptions {
  int nodes = 100; // N >= 2
  ProfileWeights weights = ProfileWeights::Gauss;
  // Set: every streamline starts at its end nearer this world RAS mm point. Unset: streamlines are flipped
  // to agree with the bundle's first (profiled) streamline, as DIPY orient_by_streamline(bundle, bundle[0]).
  std::optional<glm::dvec3> start;
  int bootstrap = 1000;     // resamples for the confidence interval (0: none, the interval is NaN)
  std::uint64_t seed = 1;   // the bootstrap's seed: the same seed gives the same interval on any machine
  double confidence = 0.95; // the interval's coverage
  int threads = 0;          // for the bootstrap; 0 = all hardware threads (the result does not depend on it)
};

// A scalar image sampled along the bundle; `volume` (component 0) on any grid.
struct ProfileScalar {
  std::string name;
  const ScalarVolume* volume = nullptr;
};

struct ScalarProfile {
  std::string name;
  // Per node: the weighted mean (or median), the standard deviation, the bootstrap interval and how many
  // streamlines had a finite value there. NaN where no streamline had one.
  std::vector<double> mean, sd, ciLow, ciHigh;
  std::vector<std::size_t> streamlines;
};

struct BundleProfile {
  std::vector<glm::dvec3> core; // per node: the weighted mean of the streamlines' node positions (world mm)
  std::vector<ScalarProfile> scalars;
  std::size_t streamlines = 0; // profiled
  std::size_t skipped = 0;     // left out: fewer than two points, or no length
  std::size_t flipped = 0;     // reversed by the orientation
};

// Profiles the streamlines `which` of `lines` (all of them when null). Throws InputError when none has two
// distinct points, and for a scalar without a volume.
BundleProfile profileBundle(const Polylines& lines, const std::vector<std::uint32_t>* which,
                            const std::vector<ProfileScalar>& scalars, const ProfileOptions& options);

// Per point of `lines` (points.size() values): the index of the node nearest it along its streamline as
// profileBundle orients and resamples the streamlines `which` (all when null) with `options` (nodes, start):
// round(s (N - 1)), s the point's arc-length fraction from the oriented streamline's start. So each oriented
// streamline's first point is node 0 and its last node N - 1. NaN on the points of the other streamlines and
// of those profileBundle skips (fewer than two points, no length). Throws InputError for an index beyond the
// lines, UsageError for fewer than 2 nodes.
std::vector<float> nodePerPoint(const Polylines& lines, const std::vector<std::uint32_t>* which,
                                const ProfileOptions& options);

// The building blocks, each as its DIPY counterpart (exposed for the tests).

// `n` points equally spaced by arc length along the polyline, the first and last on its ends
// (set_number_of_points). Needs count >= 2 and a positive length.
std::vector<glm::dvec3> resampleByArcLength(const glm::vec3* points, std::size_t count, int n);
// The total length of a polyline, mm.
double polylineLength(const glm::vec3* points, std::size_t count);
// Whether the resampled line agrees better reversed with the resampled reference: the summed distance
// between corresponding points is larger as it is than reversed (orient_by_streamline, which resamples both
// to 12 points; equal sums keep the line as it is).
bool fitsBetterReversed(const std::vector<glm::dvec3>& line, const std::vector<glm::dvec3>& reference);
// The image's component-0 value at a world RAS mm position: trilinear in its voxel frame, the neighbours
// outside the grid counting as 0, and 0 where the position is not within one voxel of the grid (strictly
// between -1 and the size along each axis), as DIPY values_from_volume (interpolate_scalar_3d).
double sampleZeroPadded(const ScalarVolume& volume, const glm::dvec3& world);
// One node's weights from the streamlines' positions there, summing to 1. Gauss: w_s proportional to
// 1 / sqrt((p_s - m)^T C^+ (p_s - m)), m the positions' mean and C their covariance (divided by the count);
// C^+ is C's inverse, or its pseudo-inverse on the directions where the positions spread (eigenvalues above
// 1e-9 of the largest: two or three streamlines, or coplanar ones). Equal weights for one position, and
// where every covariance entry is within 1e-8 mm^2 of zero (DIPY's test); positions on the mean itself share
// the whole weight (the limit of 1/d). Mean and Median: equal weights.
std::vector<double> nodeWeights(const std::vector<glm::dvec3>& positions, ProfileWeights weights);
// "inferior → superior" and the like: where a node axis from `first` to `last` starts and ends, by the
// dominant world axis of last - first (x: right/left, y: anterior/posterior, z: superior/inferior), with any
// other axis at least half as long named after it ("inferior right → superior left").
std::string nodeAxisLabel(const glm::dvec3& first, const glm::dvec3& last);

} // namespace dtf::surfaces
