// SPDX-License-Identifier: GPL-3.0-or-later
// Internals of the tensor fit shared by fitTensors (fit.cpp) and the bootstrap (bootstrap.cpp): the
// log-linear design of a gradient scheme, its pseudo-inverse and the small dense solvers. Not installed.
#pragma once

#include "io/diffusion/dwi.h"
#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace dtf::io::detail {

// Unknowns: ln S0, Dxx, Dxy, Dxz, Dyy, Dyz, Dzz. b is scaled to ms/um^2 (1e-3 s/mm^2 * 1e3) so the
// D columns are of order 1 like the ln S0 column; the fitted D is then in 1e-3 mm^2/s.
constexpr int kUnknowns = 7;
constexpr int kPacked = kUnknowns * (kUnknowns + 1) / 2; // upper triangle of a 7x7 symmetric matrix
constexpr double kBScale = 1e-3;

using Mat7 = double[kUnknowns][kUnknowns];

// Dot product with four independent partial sums: a single running sum is bound by the add latency
// (the compiler may not reassociate floating point), which dominated the per-voxel cost.
inline double dot(const double* a, const double* b, int n) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int v = 0;
  for (; v + 4 <= n; v += 4) {
    s0 += a[v] * b[v];
    s1 += a[v + 1] * b[v + 1];
    s2 += a[v + 2] * b[v + 2];
    s3 += a[v + 3] * b[v + 3];
  }
  for (; v < n; ++v)
    s0 += a[v] * b[v];
  return (s0 + s1) + (s2 + s3);
}

// In-place Cholesky A = L L^T of a symmetric 7x7 matrix (lower triangle written; the diagonal of L is
// stored inverted, so the solve multiplies instead of dividing). Returns false when a pivot is not
// positive relative to the matrix scale (singular or indefinite).
inline bool cholesky7(Mat7& a) {
  double scale = 0;
  for (int i = 0; i < kUnknowns; ++i)
    scale = std::max(scale, a[i][i]);
  if (!(scale > 0) || !std::isfinite(scale)) return false;
  for (int j = 0; j < kUnknowns; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k)
      d -= a[j][k] * a[j][k];
    if (!(d > 1e-13 * scale)) return false;
    const double inv = 1.0 / std::sqrt(d);
    a[j][j] = inv;
    for (int i = j + 1; i < kUnknowns; ++i) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k)
        s -= a[i][k] * a[j][k];
      a[i][j] = s * inv;
    }
  }
  return true;
}

// Solves L L^T x = b with the factor from cholesky7 (inverted diagonal).
inline void choleskySolve7(const Mat7& l, const double* b, double* x) {
  double y[kUnknowns];
  for (int i = 0; i < kUnknowns; ++i) {
    double s = b[i];
    for (int k = 0; k < i; ++k)
      s -= l[i][k] * y[k];
    y[i] = s * l[i][i];
  }
  for (int i = kUnknowns - 1; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k < kUnknowns; ++k)
      s -= l[k][i] * x[k];
    x[i] = s * l[i][i];
  }
}

// Everything about the gradient scheme that does not depend on the voxel, computed once.
struct Design {
  int volumes = 0;
  std::vector<double> rows;    // volumes x 7: the design matrix X
  std::vector<double> columns; // 7 x volumes: X^T, so predictions and X^T W y are contiguous dot products
  std::vector<double> pinv;    // 7 x volumes: (X^T X)^-1 X^T
  std::vector<double> outer;   // 28 x volumes: upper triangle of x_v x_v^T, so X^T W X = outer * w
};

// X^T W X of the design for per-volume weights `w` (the normal matrix of the weighted fit), symmetric.
inline void normalMatrix(const Design& design, const double* w, Mat7& a) {
  const int n = design.volumes;
  double packed[kPacked];
  for (int p = 0; p < kPacked; ++p)
    packed[p] = dot(&design.outer[static_cast<std::size_t>(p) * n], w, n);
  int p = 0;
  for (int i = 0; i < kUnknowns; ++i)
    for (int j = i; j < kUnknowns; ++j)
      a[i][j] = a[j][i] = packed[p++];
}

inline Design makeDesign(const Dwi& dwi) {
  Design d;
  d.volumes = dwi.signal.components;
  const int n = d.volumes;
  d.rows.resize(static_cast<std::size_t>(n) * kUnknowns);
  for (int v = 0; v < n; ++v) {
    const glm::dvec3 g = dwi.gradientsWorld[v];
    const double b = dwi.bvals[v] * kBScale;
    double* r = &d.rows[static_cast<std::size_t>(v) * kUnknowns];
    r[0] = 1.0;
    r[1] = -b * g.x * g.x;
    r[2] = -2.0 * b * g.x * g.y;
    r[3] = -2.0 * b * g.x * g.z;
    r[4] = -b * g.y * g.y;
    r[5] = -2.0 * b * g.y * g.z;
    r[6] = -b * g.z * g.z;
  }
  Mat7 xtx{};
  d.columns.resize(static_cast<std::size_t>(n) * kUnknowns);
  d.outer.resize(static_cast<std::size_t>(n) * kPacked);
  for (int v = 0; v < n; ++v) {
    const double* r = &d.rows[static_cast<std::size_t>(v) * kUnknowns];
    int p = 0;
    for (int i = 0; i < kUnknowns; ++i) {
      d.columns[static_cast<std::size_t>(i) * n + v] = r[i];
      for (int j = i; j < kUnknowns; ++j) {
        d.outer[static_cast<std::size_t>(p++) * n + v] = r[i] * r[j];
        xtx[i][j] += r[i] * r[j];
      }
    }
  }
  for (int i = 0; i < kUnknowns; ++i)
    for (int j = 0; j < i; ++j)
      xtx[i][j] = xtx[j][i];
  if (!cholesky7(xtx))
    throw InputError("the gradient table cannot determine a tensor: it needs at least 6 non-collinear, "
                     "non-coplanar directions with b > 0 and a volume at another b-value");
  d.pinv.resize(static_cast<std::size_t>(kUnknowns) * n);
  for (int v = 0; v < n; ++v) {
    double col[kUnknowns];
    choleskySolve7(xtx, &d.rows[static_cast<std::size_t>(v) * kUnknowns], col);
    for (int i = 0; i < kUnknowns; ++i)
      d.pinv[static_cast<std::size_t>(i) * n + v] = col[i];
  }
  return d;
}

// Positive definite by Sylvester's criterion (all leading principal minors > 0).
inline bool positiveDefinite(const double* t) { // t = xx xy xz yy yz zz
  const double m1 = t[0];
  const double m2 = t[0] * t[3] - t[1] * t[1];
  const double m3 = t[0] * (t[3] * t[5] - t[4] * t[4]) - t[1] * (t[1] * t[5] - t[4] * t[2]) +
                    t[2] * (t[1] * t[4] - t[3] * t[2]);
  return m1 > 0 && m2 > 0 && m3 > 0;
}

// The checks every tensor fit makes of its input (volume count, gradient table, signal size, minimum signal)
// and the voxels it fits: the mask's, on the DWI's grid, else the automatic mask. Throws InputError.
std::vector<unsigned char> fitVoxels(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options);

// Runs the z slices 0 .. slices-1 on options.threads threads (0: all cores), the calling thread among them
// and the only one calling `progress`. Each thread calls makeWorker() once for its own worker (which holds
// its scratch) and then worker(k, stats) for the slices it takes. The first exception stops the others and
// is rethrown after all have joined. Returns the threads' stats summed.
using SliceWorker = std::function<void(int slice, FitStats& stats)>;
FitStats forEachSlice(int slices, const FitOptions& options, const ProgressFn& progress,
                      const std::function<SliceWorker()>& makeWorker);

} // namespace dtf::io::detail
