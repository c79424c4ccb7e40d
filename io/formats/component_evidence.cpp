// SPDX-License-Identifier: GPL-3.0-or-later
// Tensor or fibre peaks: what the values of a volume with 3K components per voxel can be, judged from a
// sample of its voxels rather than from the signs of its values (sign-normalised peaks have none).
#include "io/formats/format_detail.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace dtf::io::detail {

namespace {

// At most this many voxels with data are examined (evenly spread over the volume).
constexpr std::size_t kSample = 8000;

std::string pct(double f) {
  std::ostringstream o;
  o.precision(3);
  o << 100.0 * f << "%";
  return o.str();
}

// Positive semi-definite within noise: the smallest eigenvalue is not below -1% of the largest magnitude.
// Eigenvalues only, in closed form (trigonometric; the vectors of eigenDecompose are not needed here).
bool psd(const float* c, const int* o) {
  const double a00 = c[o[0]], a01 = c[o[1]], a02 = c[o[2]], a11 = c[o[3]], a12 = c[o[4]], a22 = c[o[5]];
  const double p1 = a01 * a01 + a02 * a02 + a12 * a12;
  double hi, lo;
  if (p1 == 0) {
    hi = std::max({a00, a11, a22});
    lo = std::min({a00, a11, a22});
  } else {
    const double q = (a00 + a11 + a22) / 3;
    const double p = std::sqrt(((a00 - q) * (a00 - q) + (a11 - q) * (a11 - q) + (a22 - q) * (a22 - q) + 2 * p1) / 6);
    const double b00 = (a00 - q) / p, b11 = (a11 - q) / p, b22 = (a22 - q) / p, b01 = a01 / p, b02 = a02 / p,
                 b12 = a12 / p;
    const double det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
    const double phi = std::acos(std::clamp(det / 2, -1.0, 1.0)) / 3;
    hi = q + 2 * p * std::cos(phi);
    lo = q + 2 * p * std::cos(phi + 2.0943951023931957); // + 2 pi / 3
  }
  const double big = std::max(std::abs(hi), std::abs(lo));
  return big > 0 && lo >= -0.01 * big;
}

// The counts over the sampled voxels.
struct Tally {
  std::size_t voxels = 0, gaps = 0, partial = 0, unit = 0, multi = 0, ordered = 0, psdFsl = 0, psdMrtrix = 0;
  std::vector<std::size_t> negative, nonzero;
};

// One voxel's c = 3k values into the tally: its triplets (present, absent, partly NaN; unit; lengths
// non-increasing), the signs of its components and, for six, whether it is a tensor in either order.
void tallyVoxel(const float* x, std::size_t c, Tally& t) {
  static constexpr int kFsl[6] = {0, 1, 2, 3, 4, 5}, kMrtrix[6] = {0, 3, 4, 1, 5, 2};
  ++t.voxels;
  std::size_t present = 0, absent = 0;
  bool allUnit = true, nonIncreasing = true, partialNan = false;
  double last = 0;
  for (std::size_t k = 0; k < c / 3; ++k) {
    const float* v = x + 3 * k;
    const int nans = std::isnan(v[0]) + std::isnan(v[1]) + std::isnan(v[2]);
    if (nans == 3 || (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f)) {
      ++absent;
      continue;
    }
    if (nans > 0 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      partialNan = true;
      continue;
    }
    const double n = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
    allUnit = allUnit && std::abs(n - 1.0) < 1e-3;
    if (present > 0 && n > last * (1 + 1e-6)) nonIncreasing = false;
    last = n;
    ++present;
  }
  for (std::size_t i = 0; i < c; ++i)
    if (std::isfinite(x[i]) && x[i] != 0.0f) {
      ++t.nonzero[i];
      t.negative[i] += x[i] < 0.0f;
    }
  t.partial += partialNan;
  t.gaps += present > 0 && absent > 0;
  t.unit += present > 0 && allUnit;
  if (present > 1) {
    ++t.multi;
    t.ordered += nonIncreasing;
  }
  if (c == 6 && std::all_of(x, x + 6, [](float a) { return std::isfinite(a); })) {
    t.psdFsl += psd(x, kFsl);
    t.psdMrtrix += psd(x, kMrtrix);
  }
}

// The fractions, the words and the verdict from the tally.
void judge(const Tally& t, std::size_t c, ComponentEvidence& e) {
  const double n = double(e.voxels = t.voxels);
  e.psdFsl = double(t.psdFsl) / n;
  e.psdMrtrix = double(t.psdMrtrix) / n;
  e.tripletGaps = double(t.gaps) / n;
  e.partialNan = double(t.partial) / n;
  e.unitTriplets = double(t.unit) / n;
  e.orderedAmplitudes = t.multi ? double(t.ordered) / double(t.multi) : 0.0;
  std::size_t signedComps = 0;
  for (std::size_t i = 0; i < c; ++i)
    signedComps += t.nonzero[i] && double(t.negative[i]) >= 0.05 * double(t.nonzero[i]);
  e.signedComponents = double(signedComps) / double(c);
  const double tensorFit = std::max(e.psdFsl, e.psdMrtrix);
  // Only peaks show these: a triplet absent (zero or NaN) beside a present one, or unit vectors throughout.
  const bool strong = e.partialNan < 0.01 && (e.tripletGaps >= 0.01 || e.unitTriplets >= 0.9);
  // Peaks usually show these, other data rarely: most components signed (directions of both signs), or
  // amplitudes sorted strongest first in nearly every voxel with several peaks (sh2peaks, DIPY).
  const bool weak = e.partialNan < 0.01 &&
                    (3 * signedComps >= 2 * c || (t.multi >= 20 && e.orderedAmplitudes >= 0.99));
  std::ostringstream why;
  why << e.voxels << " sampled voxels";
  if (c == 6) why << ": positive semi-definite as FSL " << pct(e.psdFsl) << ", as MRtrix " << pct(e.psdMrtrix);
  why << "; triplets: " << pct(e.tripletGaps) << " with a peak missing, " << pct(e.unitTriplets)
      << " unit vectors, amplitudes sorted in " << pct(e.orderedAmplitudes) << ", " << signedComps << " of " << c
      << " components signed";
  if (e.partialNan >= 0.01) why << ", " << pct(e.partialNan) << " with partly-NaN triplets";
  e.evidence = why.str();
  if (c == 6 && tensorFit >= 0.9)
    e.kind = strong ? ComponentKind::Ambiguous : ComponentKind::Tensor;
  else if (c == 6 && tensorFit >= 0.5)
    e.kind = strong ? ComponentKind::Peaks : ComponentKind::Tensor;
  else
    e.kind = strong || weak ? ComponentKind::Peaks : ComponentKind::Neither;
}

} // namespace

ComponentEvidence componentEvidence(const ScalarVolume& raw) {
  ComponentEvidence e;
  const auto c = static_cast<std::size_t>(raw.components);
  const std::size_t nv = raw.grid.voxelCount();
  if (c < 3 || c % 3 != 0 || nv == 0) return e;
  // Voxels with data (a finite non-zero value), then an even sample of them.
  std::vector<std::size_t> withData;
  for (std::size_t v = 0; v < nv; ++v) {
    const float* x = &raw.data[v * c];
    if (std::any_of(x, x + c, [](float a) { return std::isfinite(a) && a != 0.0f; })) withData.push_back(v);
  }
  Tally t;
  t.negative.assign(c, 0);
  t.nonzero.assign(c, 0);
  const std::size_t stride = std::max<std::size_t>(1, withData.size() / kSample);
  for (std::size_t s = 0; s < withData.size(); s += stride)
    tallyVoxel(&raw.data[withData[s] * c], c, t);
  if (t.voxels > 0) judge(t, c, e);
  return e;
}

} // namespace dtf::io::detail
