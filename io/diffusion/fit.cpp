#include "io/diffusion/dwi.h"
#include "io/model/error.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>

namespace dtf::io {

namespace {

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
bool cholesky7(Mat7& a) {
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
void choleskySolve7(const Mat7& l, const double* b, double* x) {
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

Design makeDesign(const Dwi& dwi) {
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
bool positiveDefinite(const double* t) { // t = xx xy xz yy yz zz
  const double m1 = t[0];
  const double m2 = t[0] * t[3] - t[1] * t[1];
  const double m3 = t[0] * (t[3] * t[5] - t[4] * t[4]) - t[1] * (t[1] * t[5] - t[4] * t[2]) +
                    t[2] * (t[1] * t[4] - t[3] * t[2]);
  return m1 > 0 && m2 > 0 && m3 > 0;
}

void addStats(FitStats& total, const FitStats& s) {
  total.voxelsFitted += s.voxelsFitted;
  total.clampedSignals += s.clampedSignals;
  total.nonPositiveTensors += s.nonPositiveTensors;
  total.invalidVoxels += s.invalidVoxels;
  total.wlsFallbacks += s.wlsFallbacks;
}

// Fits one axial slice. `logs`, `weights` and `weightedLogs` are per-thread scratch of `volumes` entries.
void fitSlice(int k, const Dwi& dwi, const Design& design, const std::vector<unsigned char>& inside,
              const FitOptions& options, TensorField& out, FitStats& sliceStats, std::vector<double>& logs,
              std::vector<double>& weights, std::vector<double>& weightedLogs) {
  FitStats stats; // local: per-thread counters side by side in one vector would share cache lines
  const Grid& grid = dwi.signal.grid;
  const int n = design.volumes;
  const std::size_t slice = static_cast<std::size_t>(grid.dims.x) * grid.dims.y;
  const auto minSignal = static_cast<float>(options.minSignal);
  const double logMin = std::log(static_cast<double>(minSignal));
  for (std::size_t idx = slice * k; idx < slice * (k + 1); ++idx) {
    if (!inside[idx]) continue;
    ++stats.voxelsFitted;
    const float* s = &dwi.signal.data[idx * n];
    int clamped = 0;
    for (int v = 0; v < n; ++v) {
      if (s[v] >= minSignal) { // also false for NaN
        logs[v] = std::log(static_cast<double>(s[v]));
      } else {
        logs[v] = logMin;
        ++clamped;
      }
    }
    stats.clampedSignals += static_cast<std::size_t>(clamped);
    if (clamped == n) { // no signal at all: nothing to fit
      ++stats.invalidVoxels;
      continue;
    }
    double beta[kUnknowns];
    for (int i = 0; i < kUnknowns; ++i)
      beta[i] = dot(&design.pinv[static_cast<std::size_t>(i) * n], logs.data(), n);
    if (options.method == FitMethod::Wls) {
      // Weights S_hat^2 = exp(2 x_v . beta_ols), relative to the largest so nothing overflows.
      double* w = weights.data();
      for (int v = 0; v < n; ++v)
        w[v] = 0;
      for (int i = 0; i < kUnknowns; ++i) {
        const double* c = &design.columns[static_cast<std::size_t>(i) * n];
        for (int v = 0; v < n; ++v)
          w[v] += c[v] * beta[i];
      }
      double maxPred = -1e300;
      for (int v = 0; v < n; ++v)
        maxPred = std::max(maxPred, w[v]);
      for (int v = 0; v < n; ++v)
        w[v] = std::exp(2.0 * (w[v] - maxPred));
      double* wy = weightedLogs.data();
      for (int v = 0; v < n; ++v)
        wy[v] = w[v] * logs[v];
      double packed[kPacked], rhs[kUnknowns];
      for (int p = 0; p < kPacked; ++p)
        packed[p] = dot(&design.outer[static_cast<std::size_t>(p) * n], w, n);
      for (int i = 0; i < kUnknowns; ++i)
        rhs[i] = dot(&design.columns[static_cast<std::size_t>(i) * n], wy, n);
      Mat7 a;
      int p = 0;
      for (int i = 0; i < kUnknowns; ++i)
        for (int j = i; j < kUnknowns; ++j)
          a[i][j] = a[j][i] = packed[p++];
      if (std::isfinite(maxPred) && cholesky7(a))
        choleskySolve7(a, rhs, beta);
      else
        ++stats.wlsFallbacks;
    }
    double t[6];
    for (int i = 0; i < 6; ++i)
      t[i] = beta[i + 1] * kBScale;
    SymTensor& st = out.tensors[idx];
    st.xx = static_cast<float>(t[0]);
    st.xy = static_cast<float>(t[1]);
    st.xz = static_cast<float>(t[2]);
    st.yy = static_cast<float>(t[3]);
    st.yz = static_cast<float>(t[4]);
    st.zz = static_cast<float>(t[5]);
    if (!st.isFinite() || st.isZero()) {
      st = SymTensor{};
      ++stats.invalidVoxels;
      continue;
    }
    out.valid[idx] = 1;
    if (!positiveDefinite(t)) ++stats.nonPositiveTensors;
  }
  addStats(sliceStats, stats);
}

bool sameGrid(const Grid& a, const Grid& b) {
  if (a.dims != b.dims) return false;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (std::abs(a.voxelToWorld[c][r] - b.voxelToWorld[c][r]) > 1e-3) return false;
  return true;
}

} // namespace

TensorField fitTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                       const ProgressFn& progress, FitStats* stats) {
  const Grid& grid = dwi.signal.grid;
  const int n = dwi.signal.components;
  const std::size_t count = grid.voxelCount();
  if (n < kUnknowns)
    throw InputError("a tensor fit needs at least 7 volumes; the DWI has " + std::to_string(n));
  if (dwi.bvals.size() != static_cast<std::size_t>(n) ||
      dwi.gradientsWorld.size() != static_cast<std::size_t>(n))
    throw InputError("the gradient table has " + std::to_string(dwi.bvals.size()) + " entries for " +
                     std::to_string(n) + " DWI volumes");
  if (dwi.signal.data.size() != count * static_cast<std::size_t>(n))
    throw InputError("DWI signal size does not match its grid");
  if (!(options.minSignal > 0)) throw InputError("minimum signal must be positive");

  std::vector<unsigned char> inside;
  if (mask) {
    if (!sameGrid(mask->grid, grid) || mask->data.size() != count)
      throw InputError("the mask grid (" + std::to_string(mask->grid.dims.x) + "x" +
                       std::to_string(mask->grid.dims.y) + "x" + std::to_string(mask->grid.dims.z) +
                       ") differs from the DWI grid (" + std::to_string(grid.dims.x) + "x" +
                       std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z) + ") or its affine");
    inside.resize(count);
    for (std::size_t i = 0; i < count; ++i)
      inside[i] = mask->data[i] ? 1 : 0;
  } else {
    inside = automaticMask(dwi, options.b0Threshold).data;
  }

  const Design design = makeDesign(dwi);
  TensorField out = makeTensorField(grid);
  const int slices = grid.dims.z;
  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, std::max(1, slices));

  std::atomic<int> nextSlice{0}, doneSlices{0};
  std::atomic<bool> cancelled{false};
  std::vector<FitStats> threadStats(static_cast<std::size_t>(threads));
  auto work = [&](int t, bool reportProgress) {
    std::vector<double> logs(static_cast<std::size_t>(n)), weights(logs), weightedLogs(logs);
    for (int k = nextSlice++; k < slices && !cancelled; k = nextSlice++) {
      fitSlice(k, dwi, design, inside, options, out, threadStats[t], logs, weights, weightedLogs);
      const int done = ++doneSlices;
      if (reportProgress && progress) progress(static_cast<double>(done) / slices);
    }
  };
  std::vector<std::thread> pool;
  std::exception_ptr error;
  try {
    for (int t = 1; t < threads; ++t)
      pool.emplace_back(work, t, false);
    work(0, true); // the calling thread works too and is the only one calling `progress`
  } catch (...) {
    error = std::current_exception(); // e.g. a progress callback cancelling the fit
    cancelled = true;
  }
  for (auto& th : pool)
    th.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(1.0);
  if (stats) {
    *stats = FitStats{};
    for (const auto& s : threadStats)
      addStats(*stats, s);
  }
  return out;
}

} // namespace dtf::io
