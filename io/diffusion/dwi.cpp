// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/diffusion/dwi.h"

#include "io/formats/format_detail.h"
#include "io/formats/formats.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dtf::io {

namespace {

// Non-empty lines of a text file split into numbers; NaN is accepted (bvec b=0 rows), anything else that
// strtod does not consume completely is an error naming file and line.
struct NumberRow {
  int line = 0;
  std::vector<double> values;
};

std::vector<NumberRow> readNumberRows(const std::string& path, const char* what) {
  detail::refuseSpecialFile(path);
  std::ifstream in(path);
  if (!in) throw InputError("cannot open " + std::string(what) + " file " + path);
  std::vector<NumberRow> rows;
  std::string text;
  int lineNo = 0;
  while (std::getline(in, text)) {
    ++lineNo;
    std::istringstream tokens(text);
    std::string tok;
    NumberRow row;
    row.line = lineNo;
    while (tokens >> tok) {
      errno = 0;
      char* end = nullptr;
      double v = std::strtod(tok.c_str(), &end);
      if (end == tok.c_str() || *end != '\0')
        throw InputError(path + " line " + std::to_string(lineNo) + ": '" + tok + "' is not a number");
      row.values.push_back(v);
    }
    if (!row.values.empty()) rows.push_back(std::move(row));
  }
  if (in.bad()) throw InputError("error reading " + path);
  if (rows.empty()) throw InputError(std::string(what) + " file " + path + " holds no numbers");
  return rows;
}

std::string countText(std::size_t n, const char* unit) {
  return std::to_string(n) + " " + unit;
}

} // namespace

std::vector<double> readBvals(const std::string& path) {
  std::vector<double> out;
  for (const auto& row : readNumberRows(path, "bval")) {
    for (double v : row.values) {
      if (!std::isfinite(v) || v < 0)
        throw InputError(path + " line " + std::to_string(row.line) + ": b-value " + std::to_string(v) +
                         " is not a finite non-negative number");
      out.push_back(v);
    }
  }
  return out;
}

std::vector<glm::dvec3> readBvecs(const std::string& path, std::size_t expectedCount) {
  auto rows = readNumberRows(path, "bvec");
  std::vector<glm::dvec3> out;
  bool allSame = std::all_of(rows.begin(), rows.end(),
                             [&](const NumberRow& r) { return r.values.size() == rows[0].values.size(); });
  bool allThree =
      std::all_of(rows.begin(), rows.end(), [](const NumberRow& r) { return r.values.size() == 3; });
  if (rows.size() == 3 && allSame) { // FSL 3xN: one row per axis
    for (std::size_t n = 0; n < rows[0].values.size(); ++n)
      out.emplace_back(rows[0].values[n], rows[1].values[n], rows[2].values[n]);
  } else if (allThree) { // Nx3: one row per volume
    for (const auto& r : rows)
      out.emplace_back(r.values[0], r.values[1], r.values[2]);
  } else {
    std::string shape;
    for (std::size_t i = 0; i < rows.size() && i < 4; ++i)
      shape += (i ? ", " : "") + std::to_string(rows[i].values.size());
    if (rows.size() > 4) shape += ", ...";
    throw InputError(path + ": bvec must be 3 rows of N numbers (FSL) or N rows of 3; found " +
                     std::to_string(rows.size()) + " rows holding " + shape + " numbers");
  }
  for (std::size_t n = 0; n < out.size(); ++n) {
    for (int c = 0; c < 3; ++c) {
      if (std::isinf(out[n][c])) throw InputError(path + ": direction " + std::to_string(n) + " is infinite");
    }
  }
  if (expectedCount > 0 && out.size() != expectedCount)
    throw InputError(path + " holds " + countText(out.size(), "directions") + ", expected " +
                     std::to_string(expectedCount));
  return out;
}

glm::dmat3 bvecFrameToWorld(const Grid& grid) {
  glm::dmat3 flip(1.0);
  if (glm::determinant(glm::dmat3(grid.voxelToWorld)) > 0) flip[0][0] = -1.0;
  return grid.rotation() * flip;
}

Dwi makeDwi(Volume<float> signal, std::vector<double> bvals, const std::vector<glm::dvec3>& bvecs,
            double b0Threshold, const std::string& dwiName, const std::string& bvalName,
            const std::string& bvecName) {
  const std::size_t volumes = static_cast<std::size_t>(std::max(signal.components, 0));
  if (bvals.size() != volumes)
    throw InputError(bvalName + " holds " + countText(bvals.size(), "b-values") + " but " + dwiName +
                     " has " + countText(volumes, "volumes"));
  if (bvecs.size() != volumes)
    throw InputError(bvecName + " holds " + countText(bvecs.size(), "directions") + " but " + dwiName +
                     " has " + countText(volumes, "volumes"));
  const glm::dmat3 toWorld = bvecFrameToWorld(signal.grid);
  Dwi dwi;
  dwi.gradientsWorld.resize(volumes, glm::dvec3(0.0));
  double worstNorm = 1.0;
  std::size_t worstIndex = 0;
  for (std::size_t n = 0; n < volumes; ++n) {
    const glm::dvec3& g = bvecs[n];
    bool finite = std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z);
    double norm = finite ? glm::length(g) : 0.0;
    if (!(norm > 1e-6)) {
      if (bvals[n] > b0Threshold)
        throw InputError(bvecName + ": volume " + std::to_string(n) + " has b = " + std::to_string(bvals[n]) +
                         " s/mm^2 (above the b=0 threshold " + std::to_string(b0Threshold) + ") but a " +
                         (finite ? "zero" : "NaN") + " gradient direction");
      continue; // b=0 volume without a direction
    }
    if (std::abs(norm - 1.0) > std::abs(worstNorm - 1.0)) {
      worstNorm = norm;
      worstIndex = n;
    }
    dwi.gradientsWorld[n] = glm::normalize(toWorld * (g / norm));
  }
  if (std::abs(worstNorm - 1.0) > 0.1)
    logWarning(bvecName + ": gradient directions are not unit vectors (volume " + std::to_string(worstIndex) +
               " has norm " + std::to_string(worstNorm) + "); they were normalised and the b-values kept");
  dwi.signal = std::move(signal);
  dwi.bvals = std::move(bvals);
  return dwi;
}

namespace {

// The DWI with the gradient table stored in the file (MRtrix dw_scheme, DSI Studio b_table).
Dwi readStoredDwi(const std::string& path, const FormatGuess& format, double b0Threshold) {
  try {
    detail::StoredGradients s = detail::readStoredGradients(path, format);
    // makeDwi takes the bvec frame, which R*F maps to world.
    const glm::dmat3 toBvec = glm::inverse(bvecFrameToWorld(s.signal.grid)) * s.directionsToWorld;
    std::vector<glm::dvec3> bvecs;
    for (const glm::dvec3& d : s.directions)
      bvecs.push_back(toBvec * d);
    const std::string label = path + " " + s.table;
    Dwi dwi = makeDwi(std::move(s.signal), std::move(s.bvals), bvecs, b0Threshold, path, label, label);
    dwi.path = path;
    dwi.bvalPath = dwi.bvecPath = path + " (" + s.table + ")";
    return dwi;
  } catch (...) {
    rethrowWithContext("while reading DWI " + path);
  }
}

} // namespace

Dwi readDwi(const std::string& dwiPath, const std::string& bvalPath, const std::string& bvecPath,
            double b0Threshold) {
  return readDwi(dwiPath, detectFormat(dwiPath), bvalPath, bvecPath, b0Threshold);
}

Dwi readDwi(const std::string& dwiPath, const FormatGuess& format, const std::string& bvalPath,
            const std::string& bvecPath, double b0Threshold) {
  if (bvalPath.empty() && bvecPath.empty()) return readStoredDwi(dwiPath, format, b0Threshold);
  try {
    VolumeHeader header;
    ScalarVolume signal = readScalarVolume(dwiPath, format, &header);
    if (signal.components < 2)
      throw InputError(dwiPath + " is not a 4D diffusion series (it holds " +
                       countText(static_cast<std::size_t>(signal.components), "volume") + ")");
    std::vector<double> bvals = readBvals(bvalPath);
    std::vector<glm::dvec3> bvecs = readBvecs(bvecPath);
    Dwi dwi = makeDwi(std::move(signal), std::move(bvals), bvecs, b0Threshold, dwiPath, bvalPath, bvecPath);
    dwi.path = dwiPath;
    dwi.bvalPath = bvalPath;
    dwi.bvecPath = bvecPath;
    return dwi;
  } catch (...) {
    rethrowWithContext("while reading DWI " + dwiPath);
  }
}

namespace {

// Otsu's threshold over the finite positive values of `v` (256-bin histogram).
double otsuThreshold(const std::vector<float>& v) {
  float lo = 0, hi = 0;
  bool any = false;
  for (float x : v) {
    if (!(x > 0) || !std::isfinite(x)) continue;
    lo = any ? std::min(lo, x) : x;
    hi = any ? std::max(hi, x) : x;
    any = true;
  }
  if (!any || hi <= lo) return lo;
  constexpr int kBins = 256;
  std::vector<double> hist(kBins, 0.0);
  const double scale = (kBins - 1) / static_cast<double>(hi - lo);
  for (float x : v)
    if (x > 0 && std::isfinite(x)) hist[static_cast<int>((x - lo) * scale)] += 1;
  double total = 0, sumAll = 0;
  for (int b = 0; b < kBins; ++b) {
    total += hist[b];
    sumAll += b * hist[b];
  }
  double w0 = 0, sum0 = 0, best = -1;
  int bestBin = 0;
  for (int b = 0; b < kBins - 1; ++b) {
    w0 += hist[b];
    sum0 += b * hist[b];
    double w1 = total - w0;
    if (w0 == 0 || w1 == 0) continue;
    double m0 = sum0 / w0, m1 = (sumAll - sum0) / w1;
    double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      bestBin = b;
    }
  }
  return lo + (bestBin + 1) / scale; // values in bins above bestBin are foreground
}

// The b=0 volumes (the lowest-b ones when none is at most b0Threshold) and the others.
void splitVolumes(const Dwi& dwi, double b0Threshold, std::vector<int>& b0, std::vector<int>& dw) {
  const Grid& grid = dwi.signal.grid;
  const int volumes = dwi.signal.components;
  if (volumes < 1 || dwi.bvals.size() != static_cast<std::size_t>(volumes) ||
      dwi.signal.data.size() != grid.voxelCount() * static_cast<std::size_t>(volumes))
    throw InputError("automatic mask: DWI signal and b-values do not match");
  b0.clear();
  dw.clear();
  for (int v = 0; v < volumes; ++v)
    if (dwi.bvals[v] <= b0Threshold) b0.push_back(v);
  if (b0.empty()) {
    double minB = *std::min_element(dwi.bvals.begin(), dwi.bvals.end());
    for (int v = 0; v < volumes; ++v)
      if (dwi.bvals[v] == minB) b0.push_back(v);
  }
  for (int v = 0; v < volumes; ++v)
    if (std::find(b0.begin(), b0.end(), v) == b0.end()) dw.push_back(v);
}

// The mean over `vols` per voxel (zeros when `vols` is empty).
std::vector<float> meanOf(const Dwi& dwi, const std::vector<int>& vols) {
  const std::size_t count = dwi.signal.grid.voxelCount();
  const int volumes = dwi.signal.components;
  std::vector<float> mean(count, 0.0f);
  if (vols.empty()) return mean;
  for (std::size_t i = 0; i < count; ++i) {
    double s = 0;
    for (int v : vols)
      s += dwi.signal.data[i * volumes + v];
    mean[i] = static_cast<float>(s / static_cast<double>(vols.size()));
  }
  return mean;
}

// Marks in `mask` the voxels whose finite `mean` is at least kSignalFraction of its 99th percentile.
void markSignal(const std::vector<float>& mean, MaskVolume& mask) {
  std::vector<float> finite;
  finite.reserve(mean.size());
  for (float v : mean)
    if (std::isfinite(v)) finite.push_back(v);
  if (finite.empty()) return;
  const std::size_t k = std::min(finite.size() - 1, static_cast<std::size_t>(0.99 * (finite.size() - 1) + 0.5));
  std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(k), finite.end());
  const double p99 = finite[k];
  if (!(p99 > 0)) return;
  for (std::size_t i = 0; i < mean.size(); ++i)
    if (std::isfinite(mean[i]) && mean[i] > 0 && mean[i] >= kSignalFraction * p99) mask.data[i] = 1;
}

MaskVolume signalMaskOf(const Grid& grid, const std::vector<float>& b0Mean, const std::vector<float>& dwMean,
                        bool hasDw) {
  MaskVolume signal(grid, 1, 0);
  markSignal(b0Mean, signal);
  if (hasDw) markSignal(dwMean, signal);
  return signal;
}

} // namespace

MaskVolume signalMask(const Dwi& dwi, double b0Threshold) {
  std::vector<int> b0, dw;
  splitVolumes(dwi, b0Threshold, b0, dw);
  return signalMaskOf(dwi.signal.grid, meanOf(dwi, b0), meanOf(dwi, dw), !dw.empty());
}

std::string automaticMaskWarning(const AutomaticMaskReport& r) {
  if (r.signalVoxels == 0 || 2 * r.keptSignal >= r.signalVoxels) return {};
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "the automatic mask keeps %zu of the %zu voxels holding signal (%.0f%%): if the data has no "
                "background to remove (a phantom, a crop of tissue), give a mask with --mask FILE",
                r.keptSignal, r.signalVoxels, 100.0 * double(r.keptSignal) / double(r.signalVoxels));
  return buf;
}

MaskVolume automaticMask(const Dwi& dwi, double b0Threshold, AutomaticMaskReport* report) {
  const Grid& grid = dwi.signal.grid;
  const std::size_t count = grid.voxelCount();
  std::vector<int> b0, dw;
  splitVolumes(dwi, b0Threshold, b0, dw);
  const std::vector<float> b0Mean = meanOf(dwi, b0), dwMean = meanOf(dwi, dw);
  const MaskVolume signal = signalMaskOf(grid, b0Mean, dwMean, !dw.empty());
  std::size_t signalVoxels = 0;
  for (auto v : signal.data) signalVoxels += v;
  const auto finish = [&](MaskVolume mask, bool noBackground) {
    if (report) {
      *report = AutomaticMaskReport{};
      report->voxels = count;
      report->signalVoxels = signalVoxels;
      report->noBackground = noBackground;
      for (std::size_t i = 0; i < count; ++i) {
        report->kept += mask.data[i];
        report->keptSignal += mask.data[i] && signal.data[i];
      }
    }
    return mask;
  };
  // No background to split off: Otsu would split the tissue (or the noise of a uniform phantom) in two.
  if (count > 0 && static_cast<double>(signalVoxels) >= kNoBackgroundFraction * static_cast<double>(count))
    return finish(signal, true);

  MaskVolume mask(grid, 1, 0);
  for (const std::vector<float>* means : {&b0Mean, &dwMean}) {
    if (means == &dwMean && dw.empty()) continue;
    const std::vector<float>& mean = *means;
    const double threshold = otsuThreshold(mean);
    for (std::size_t i = 0; i < count; ++i)
      if (mean[i] >= threshold && mean[i] > 0) mask.data[i] = 1;
  }

  // Largest 6-connected component: label by breadth-first search, keep the biggest label.
  const glm::ivec3 d = grid.dims;
  std::vector<int> label(count, 0), queue;
  queue.reserve(count / 4);
  int bestLabel = 0, next = 0;
  std::size_t bestSize = 0;
  for (std::size_t seed = 0; seed < count; ++seed) {
    if (!mask.data[seed] || label[seed]) continue;
    label[seed] = ++next;
    queue.assign(1, static_cast<int>(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int idx = queue[q];
      const int i = idx % d.x, j = (idx / d.x) % d.y, k = idx / (d.x * d.y);
      const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                            {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
      for (const auto& n : nb) {
        if (!grid.contains(n[0], n[1], n[2])) continue;
        const std::size_t ni = grid.index(n[0], n[1], n[2]);
        if (mask.data[ni] && !label[ni]) {
          label[ni] = next;
          queue.push_back(static_cast<int>(ni));
        }
      }
    }
    if (queue.size() > bestSize) {
      bestSize = queue.size();
      bestLabel = next;
    }
  }
  for (std::size_t i = 0; i < count; ++i)
    mask.data[i] = bestLabel && label[i] == bestLabel ? 1 : 0;

  // Fill holes per axial slice: background not reachable from the slice border becomes brain.
  std::vector<unsigned char> outside;
  std::vector<int> stack;
  for (int k = 0; k < d.z; ++k) {
    outside.assign(static_cast<std::size_t>(d.x) * d.y, 0);
    stack.clear();
    auto push = [&](int i, int j) {
      const std::size_t p = static_cast<std::size_t>(i) + static_cast<std::size_t>(d.x) * j;
      if (!outside[p] && !mask.data[grid.index(i, j, k)]) {
        outside[p] = 1;
        stack.push_back(static_cast<int>(p));
      }
    };
    for (int i = 0; i < d.x; ++i) {
      push(i, 0);
      push(i, d.y - 1);
    }
    for (int j = 0; j < d.y; ++j) {
      push(0, j);
      push(d.x - 1, j);
    }
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      const int i = p % d.x, j = p / d.x;
      if (i > 0) push(i - 1, j);
      if (i + 1 < d.x) push(i + 1, j);
      if (j > 0) push(i, j - 1);
      if (j + 1 < d.y) push(i, j + 1);
    }
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i)
        if (!outside[static_cast<std::size_t>(i) + static_cast<std::size_t>(d.x) * j]) mask.at(i, j, k) = 1;
  }
  return finish(std::move(mask), false);
}

} // namespace dtf::io
