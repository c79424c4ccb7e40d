// SPDX-License-Identifier: GPL-3.0-or-later
// Wild bootstrap of the tensor fit and the cone of uncertainty (io/uncertainty.h).
#include "io/diffusion/fit_detail.h"
#include "io/diffusion/uncertainty.h"
#include "io/model/tensor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace dtf::io {

namespace {

using namespace detail;

constexpr double kRadToDeg = 57.29577951308232;

// Principal eigenvector of a symmetric 3x3 (t = xx xy xz yy yz zz): the largest eigenvalue in closed form
// (trigonometric), then the largest cross product of two rows of T - l1 I. Any unit vector for an
// isotropic tensor. Cheaper than eigenDecompose, which also builds e2 and e3.
glm::dvec3 principalDirection(const double* t) {
  const double q = (t[0] + t[3] + t[5]) / 3.0;
  const double p1 = t[1] * t[1] + t[2] * t[2] + t[4] * t[4];
  const double a = t[0] - q, b = t[3] - q, c = t[5] - q;
  const double p2 = a * a + b * b + c * c + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  if (!(p > 1e-12 * (std::abs(q) + 1e-30))) return {1.0, 0.0, 0.0};
  const double ip = 1.0 / p;
  const double ba = a * ip, bb = b * ip, bc = c * ip, bxy = t[1] * ip, bxz = t[2] * ip, byz = t[4] * ip;
  const double det = ba * (bb * bc - byz * byz) - bxy * (bxy * bc - byz * bxz) + bxz * (bxy * byz - bb * bxz);
  const double r = std::clamp(0.5 * det, -1.0, 1.0);
  const double l1 = q + 2.0 * p * std::cos(std::acos(r) / 3.0);
  const glm::dvec3 r0(t[0] - l1, t[1], t[2]), r1(t[1], t[3] - l1, t[4]), r2(t[2], t[4], t[5] - l1);
  const glm::dvec3 c01 = glm::cross(r0, r1), c02 = glm::cross(r0, r2), c12 = glm::cross(r1, r2);
  const double n01 = glm::dot(c01, c01), n02 = glm::dot(c02, c02), n12 = glm::dot(c12, c12);
  glm::dvec3 best = c01;
  double nb = n01;
  if (n02 > nb) best = c02, nb = n02;
  if (n12 > nb) best = c12, nb = n12;
  if (!(nb > 0)) return {1.0, 0.0, 0.0};
  return best / std::sqrt(nb);
}

double faOf(const double* t) {
  const double q = (t[0] + t[3] + t[5]) / 3.0;
  const double a = t[0] - q, b = t[3] - q, c = t[5] - q;
  const double off = t[1] * t[1] + t[2] * t[2] + t[4] * t[4];
  const double dev = a * a + b * b + c * c + 2.0 * off;
  const double all = t[0] * t[0] + t[3] * t[3] + t[5] * t[5] + 2.0 * off;
  return all > 0 ? std::min(1.0, std::sqrt(1.5 * dev / all)) : 0.0;
}

// Per-thread scratch.
struct Scratch {
  std::vector<double> logs, w, fitted, h; // n; h: 7 x n hat rows
  std::vector<float> g;                   // 6 x n: H rows 1..6 times the scaled residuals
  std::vector<float> out;                 // 6 x N resampled tensors (1e-3 mm^2/s)
  std::vector<glm::vec3> dirs;            // N
  std::vector<float> angles;              // N
  Scratch(int n, int resamples)
      : logs(n), w(n), fitted(n), h(static_cast<std::size_t>(kUnknowns) * n),
        g(static_cast<std::size_t>(6) * n), out(static_cast<std::size_t>(6) * resamples), dirs(resamples),
        angles(resamples) {}
};

struct Job {
  const Dwi& dwi;
  const Design& design;
  const std::vector<unsigned char>& inside;
  const FitOptions& options;
  const BootstrapOptions& bootstrap;
  const std::vector<float>& signs; // n x N, +-1
  TensorField& out;
  UncertaintyMaps& maps;
};

void bootstrapSlice(int k, const Job& job, Scratch& s, FitStats& sliceStats) {
  FitStats stats;
  const Grid& grid = job.dwi.signal.grid;
  const int n = job.design.volumes;
  const int N = job.bootstrap.resamples;
  const std::size_t slice = static_cast<std::size_t>(grid.dims.x) * grid.dims.y;
  const auto minSignal = static_cast<float>(job.options.minSignal);
  const double logMin = std::log(static_cast<double>(minSignal));
  const Design& d = job.design;
  for (std::size_t idx = slice * k; idx < slice * (k + 1); ++idx) {
    if (!job.inside[idx]) continue;
    ++stats.voxelsFitted;
    const float* sig = &job.dwi.signal.data[idx * n];
    int clamped = 0;
    for (int v = 0; v < n; ++v) {
      if (sig[v] >= minSignal) {
        s.logs[v] = std::log(static_cast<double>(sig[v]));
      } else {
        s.logs[v] = logMin;
        ++clamped;
      }
    }
    stats.clampedSignals += static_cast<std::size_t>(clamped);
    if (clamped == n) {
      ++stats.invalidVoxels;
      continue;
    }
    double beta[kUnknowns];
    for (int i = 0; i < kUnknowns; ++i)
      beta[i] = dot(&d.pinv[static_cast<std::size_t>(i) * n], s.logs.data(), n);
    // Weights: 1 (OLS) or S_hat^2 from the OLS prediction (WLS), as fitTensors.
    bool weighted = job.options.method == FitMethod::Wls;
    if (weighted) {
      double maxPred = -1e300;
      for (int v = 0; v < n; ++v) {
        s.w[v] = dot(&d.rows[static_cast<std::size_t>(v) * kUnknowns], beta, kUnknowns);
        maxPred = std::max(maxPred, s.w[v]);
      }
      for (int v = 0; v < n; ++v)
        s.w[v] = std::exp(2.0 * (s.w[v] - maxPred));
      weighted = std::isfinite(maxPred);
    }
    if (!weighted) std::fill(s.w.begin(), s.w.end(), 1.0);
    Mat7 a;
    normalMatrix(d, s.w.data(), a);
    if (!cholesky7(a)) {
      if (!weighted) {
        ++stats.invalidVoxels;
        continue;
      }
      ++stats.wlsFallbacks; // as fitTensors: keep OLS
      std::fill(s.w.begin(), s.w.end(), 1.0);
      normalMatrix(d, s.w.data(), a);
      if (!cholesky7(a)) {
        ++stats.invalidVoxels;
        continue;
      }
    }
    // Hat rows H = A^-1 X^T W (7 x n) and the refit beta = H y.
    for (int v = 0; v < n; ++v) {
      double col[kUnknowns];
      choleskySolve7(a, &d.rows[static_cast<std::size_t>(v) * kUnknowns], col);
      for (int i = 0; i < kUnknowns; ++i)
        s.h[static_cast<std::size_t>(i) * n + v] = col[i] * s.w[v];
    }
    for (int i = 0; i < kUnknowns; ++i)
      beta[i] = dot(&s.h[static_cast<std::size_t>(i) * n], s.logs.data(), n);
    double t[6];
    for (int i = 0; i < 6; ++i)
      t[i] = beta[i + 1];
    SymTensor& st = job.out.tensors[idx];
    st = SymTensor{static_cast<float>(t[0] * kBScale), static_cast<float>(t[1] * kBScale),
                   static_cast<float>(t[2] * kBScale), static_cast<float>(t[3] * kBScale),
                   static_cast<float>(t[4] * kBScale), static_cast<float>(t[5] * kBScale)};
    if (!st.isFinite() || st.isZero()) {
      st = SymTensor{};
      ++stats.invalidVoxels;
      continue;
    }
    job.out.valid[idx] = 1;
    {
      double tt[6];
      for (int i = 0; i < 6; ++i)
        tt[i] = t[i] * kBScale;
      if (!positiveDefinite(tt)) ++stats.nonPositiveTensors;
    }
    // Leverage-scaled residuals r_v / sqrt(1 - h_vv), h_vv = x_v . H[:, v].
    for (int v = 0; v < n; ++v) {
      const double* x = &d.rows[static_cast<std::size_t>(v) * kUnknowns];
      double fit = 0, lev = 0;
      for (int i = 0; i < kUnknowns; ++i) {
        fit += x[i] * beta[i];
        lev += x[i] * s.h[static_cast<std::size_t>(i) * n + v];
      }
      const double r = (s.logs[v] - fit) / std::sqrt(std::max(1.0 - lev, 1e-3));
      for (int i = 0; i < 6; ++i)
        s.g[static_cast<std::size_t>(i) * n + v] =
            static_cast<float>(s.h[static_cast<std::size_t>(i + 1) * n + v] * r);
    }
    // The N refits at once: out = beta + G T (6 x n times n x N, sign matrix shared by all voxels).
    for (int i = 0; i < 6; ++i) {
      float* o = &s.out[static_cast<std::size_t>(i) * N];
      const auto b = static_cast<float>(t[i]);
      for (int r = 0; r < N; ++r)
        o[r] = b;
      const float* gi = &s.g[static_cast<std::size_t>(i) * n];
      for (int v = 0; v < n; ++v) {
        const float gv = gi[v];
        const float* sg = &job.signs[static_cast<std::size_t>(v) * N];
        for (int r = 0; r < N; ++r)
          o[r] += gv * sg[r];
      }
    }
    double dyad[6] = {0, 0, 0, 0, 0, 0};
    double faSum = 0, faSq = 0;
    for (int r = 0; r < N; ++r) {
      double tr[6];
      for (int i = 0; i < 6; ++i)
        tr[i] = s.out[static_cast<std::size_t>(i) * N + r];
      const glm::dvec3 e = principalDirection(tr);
      s.dirs[r] = glm::vec3(e);
      dyad[0] += e.x * e.x, dyad[1] += e.x * e.y, dyad[2] += e.x * e.z;
      dyad[3] += e.y * e.y, dyad[4] += e.y * e.z, dyad[5] += e.z * e.z;
      const double fa = faOf(tr);
      faSum += fa;
      faSq += fa * fa;
    }
    const glm::dvec3 mean = principalDirection(dyad);
    for (int r = 0; r < N; ++r) {
      const double c = std::min(1.0, std::abs(glm::dot(glm::dvec3(s.dirs[r]), mean)));
      s.angles[r] = static_cast<float>(std::acos(c) * kRadToDeg);
    }
    const auto rank = static_cast<std::size_t>(
        std::clamp(std::ceil(job.bootstrap.percentile / 100.0 * N) - 1.0, 0.0, static_cast<double>(N - 1)));
    std::nth_element(s.angles.begin(), s.angles.begin() + static_cast<std::ptrdiff_t>(rank), s.angles.end());
    job.maps.cone.data[idx] = s.angles[rank];
    const double faMean = faSum / N;
    job.maps.faSd.data[idx] =
        static_cast<float>(std::sqrt(std::max(0.0, (faSq - N * faMean * faMean) / (N - 1))));
  }
  sliceStats.voxelsFitted += stats.voxelsFitted;
  sliceStats.clampedSignals += stats.clampedSignals;
  sliceStats.nonPositiveTensors += stats.nonPositiveTensors;
  sliceStats.invalidVoxels += stats.invalidVoxels;
  sliceStats.wlsFallbacks += stats.wlsFallbacks;
}

} // namespace

DirectionSpread directionSpread(const glm::vec3* directions, std::size_t count, double percentile) {
  DirectionSpread out;
  double dyad[6] = {0, 0, 0, 0, 0, 0};
  std::vector<glm::dvec3> unit;
  unit.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 d(directions[i]);
    const double len = glm::length(d);
    if (!(len > 1e-12) || !std::isfinite(len)) continue;
    const glm::dvec3 e = d / len;
    unit.push_back(e);
    dyad[0] += e.x * e.x, dyad[1] += e.x * e.y, dyad[2] += e.x * e.z;
    dyad[3] += e.y * e.y, dyad[4] += e.y * e.z, dyad[5] += e.z * e.z;
  }
  out.samples = static_cast<int>(unit.size());
  if (unit.empty()) return out;
  out.mean = principalDirection(dyad);
  std::vector<double> angles;
  angles.reserve(unit.size());
  for (const auto& e : unit)
    angles.push_back(std::acos(std::min(1.0, std::abs(glm::dot(e, out.mean)))) * kRadToDeg);
  const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(percentile / 100.0 * angles.size()) - 1.0,
                                                        0.0, static_cast<double>(angles.size() - 1)));
  std::nth_element(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(rank), angles.end());
  out.coneDeg = angles[rank];
  return out;
}

TensorField bootstrapTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                             const BootstrapOptions& bootstrap, UncertaintyMaps& maps,
                             const ProgressFn& progress, FitStats* stats) {
  const Grid& grid = dwi.signal.grid;
  const int n = dwi.signal.components;
  if (bootstrap.resamples < 2 || bootstrap.resamples > 100000)
    throw InputError("a bootstrap needs 2 to 100000 resamples; asked for " +
                     std::to_string(bootstrap.resamples));
  if (!(bootstrap.percentile > 0 && bootstrap.percentile < 100))
    throw InputError("the cone's percentile must lie in (0, 100)");
  const std::vector<unsigned char> inside = fitVoxels(dwi, mask, options);
  const Design design = makeDesign(dwi);
  const int N = bootstrap.resamples;
  std::vector<float> signs(static_cast<std::size_t>(n) * N);
  std::mt19937_64 rng(bootstrap.seed);
  for (auto& sgn : signs)
    sgn = (rng() >> 63) != 0 ? 1.0f : -1.0f;

  TensorField out = makeTensorField(grid);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  maps.cone = ScalarVolume(grid, 1, nan);
  maps.faSd = ScalarVolume(grid, 1, nan);
  const Job job{dwi, design, inside, options, bootstrap, signs, out, maps};

  const FitStats total = forEachSlice(grid.dims.z, options, progress, [&]() -> SliceWorker {
    return [&, scratch = Scratch(n, N)](int k, FitStats& sliceStats) mutable {
      bootstrapSlice(k, job, scratch, sliceStats);
    };
  });
  if (stats) *stats = total;
  return out;
}

} // namespace dtf::io
