// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/diffusion/dwi.h"
#include "io/diffusion/fit_detail.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>

namespace dtf::io {

namespace {

using namespace detail;

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
      double rhs[kUnknowns];
      for (int i = 0; i < kUnknowns; ++i)
        rhs[i] = dot(&design.columns[static_cast<std::size_t>(i) * n], wy, n);
      Mat7 a;
      normalMatrix(design, w, a);
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

} // namespace

std::vector<unsigned char> detail::fitVoxels(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options) {
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
    if (!mask->grid.sameAs(grid) || mask->data.size() != count)
      throw InputError("the mask grid (" + std::to_string(mask->grid.dims.x) + "x" +
                       std::to_string(mask->grid.dims.y) + "x" + std::to_string(mask->grid.dims.z) +
                       ") differs from the DWI grid (" + std::to_string(grid.dims.x) + "x" +
                       std::to_string(grid.dims.y) + "x" + std::to_string(grid.dims.z) + ") or its affine");
    inside.resize(count);
    for (std::size_t i = 0; i < count; ++i)
      inside[i] = mask->data[i] ? 1 : 0;
  } else {
    AutomaticMaskReport report;
    inside = automaticMask(dwi, options.b0Threshold, &report).data;
    if (report.noBackground)
      logInfo("automatic mask: " + std::to_string(report.signalVoxels) + " of " + std::to_string(report.voxels) +
              " voxels hold signal (no background): all of them are fitted");
    if (const std::string warning = automaticMaskWarning(report); !warning.empty()) logWarning(warning);
  }
  return inside;
}

FitStats detail::forEachSlice(int slices, const FitOptions& options, const ProgressFn& progress,
                      const std::function<SliceWorker()>& makeWorker) {
  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, std::max(1, slices));
  std::atomic<int> nextSlice{0}, doneSlices{0};
  std::atomic<bool> cancelled{false};
  std::vector<FitStats> threadStats(static_cast<std::size_t>(threads));
  auto work = [&](int t, bool reportProgress) {
    const SliceWorker worker = makeWorker();
    for (int k = nextSlice++; k < slices && !cancelled; k = nextSlice++) {
      worker(k, threadStats[static_cast<std::size_t>(t)]);
      const int done = ++doneSlices;
      if (reportProgress && progress) progress(static_cast<double>(done) / slices);
    }
  };
  std::vector<std::thread> pool;
  std::exception_ptr error;
  try {
    for (int t = 1; t < threads; ++t)
      pool.emplace_back(work, t, false);
    work(0, true);
  } catch (...) {
    error = std::current_exception(); // e.g. a progress callback cancelling the fit
    cancelled = true;
  }
  for (auto& th : pool)
    th.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(1.0);
  FitStats total;
  for (const auto& s : threadStats)
    addStats(total, s);
  return total;
}

TensorField fitTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                       const ProgressFn& progress, FitStats* stats) {
  const Grid& grid = dwi.signal.grid;
  const int n = dwi.signal.components;
  const std::vector<unsigned char> inside = fitVoxels(dwi, mask, options);
  const Design design = makeDesign(dwi);
  TensorField out = makeTensorField(grid);
  const FitStats total = forEachSlice(grid.dims.z, options, progress, [&]() -> SliceWorker {
    const std::vector<double> scratch(static_cast<std::size_t>(n));
    return [&, logs = scratch, weights = scratch, weightedLogs = scratch](int k, FitStats& sliceStats) mutable {
      fitSlice(k, dwi, design, inside, options, out, sliceStats, logs, weights, weightedLogs);
    };
  });
  if (stats) *stats = total;
  return out;
}

} // namespace dtf::io
