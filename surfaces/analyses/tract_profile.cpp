// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/analyses/tract_profile.h"

#include "io/model/error.h"
#include "io/model/tensor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <thread>

namespace dtf::surfaces {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kOrientPoints = 12; // DIPY orient_by_streamline's default resampling

// SplitMix64: a small, well-mixed generator whose sequence is the same on every platform (the bootstrap's
// draws must not depend on the standard library's distributions).
std::uint64_t splitMix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void weightsInto(const glm::dvec3* p, std::size_t n, ProfileWeights mode, std::vector<double>& w) {
  w.assign(n, n ? 1.0 / static_cast<double>(n) : 0.0);
  if (mode != ProfileWeights::Gauss || n < 2) return;
  glm::dvec3 m(0.0);
  for (std::size_t s = 0; s < n; ++s)
    m += p[s];
  m /= static_cast<double>(n);
  glm::dmat3 c(0.0);
  for (std::size_t s = 0; s < n; ++s) {
    const glm::dvec3 d = p[s] - m;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c[a][b] += d[a] * d[b];
  }
  c /= static_cast<double>(n);
  bool zero = true;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      zero = zero && std::abs(c[a][b]) <= 1e-8;
  if (zero) return;
  const EigenSystem e = eigenDecompose(c);
  const double largest = e.values[0];
  const bool fullRank = e.values[2] > 1e-9 * largest;
  const glm::dmat3 inverse = fullRank ? glm::inverse(c) : glm::dmat3(0.0);
  std::size_t onMean = 0;
  for (std::size_t s = 0; s < n; ++s) {
    const glm::dvec3 d = p[s] - m;
    double d2 = 0;
    if (fullRank) {
      d2 = glm::dot(d, inverse * d);
    } else {
      for (int i = 0; i < 3; ++i)
        if (e.values[i] > 1e-9 * largest) d2 += std::pow(glm::dot(e.vectors[i], d), 2) / e.values[i];
    }
    w[s] = std::sqrt(std::max(d2, 0.0));
    if (w[s] <= 1e-12) ++onMean;
  }
  if (onMean) {
    for (double& x : w)
      x = x <= 1e-12 ? 1.0 / static_cast<double>(onMean) : 0.0;
    return;
  }
  double sum = 0;
  for (double& x : w)
    sum += (x = 1.0 / x);
  for (double& x : w)
    x /= sum;
}

// The node's centre (weighted mean, or median) of the finite values, with their count; NaN when none.
double centreOf(const std::vector<double>& v, const std::vector<double>& w, ProfileWeights mode,
                std::vector<double>& scratch, std::size_t* count = nullptr) {
  scratch.clear();
  double sum = 0, wsum = 0, plain = 0;
  std::size_t finite = 0;
  for (std::size_t j = 0; j < v.size(); ++j) {
    if (!std::isfinite(v[j])) continue;
    if (mode == ProfileWeights::Median) scratch.push_back(v[j]);
    ++finite;
    sum += w[j] * v[j];
    wsum += w[j];
    plain += v[j];
  }
  if (count) *count = finite;
  if (finite == 0) return kNaN;
  if (mode == ProfileWeights::Median) {
    const std::size_t h = scratch.size() / 2;
    std::nth_element(scratch.begin(), scratch.begin() + h, scratch.end());
    const double upper = scratch[h];
    if (scratch.size() % 2) return upper;
    return 0.5 * (upper + *std::max_element(scratch.begin(), scratch.begin() + h));
  }
  if (wsum > 0) return sum / wsum;
  // The whole weight went to streamlines without a value here: the finite values count alike.
  return plain / static_cast<double>(finite);
}

// The spread of the finite values about `centre`: the weighted standard deviation with the reliability
// weights' correction, sqrt(sum w (v - c)^2 / (1 - sum w^2)) for weights normalised over the finite values
// (equal weights: the sample standard deviation, n - 1); the median's is the sample standard deviation
// about the mean. NaN for fewer than two values or weights all on one.
double spreadOf(const std::vector<double>& v, const std::vector<double>& w, ProfileWeights mode,
                double centre) {
  std::size_t n = 0;
  double wsum = 0;
  for (std::size_t j = 0; j < v.size(); ++j)
    if (std::isfinite(v[j])) {
      ++n;
      wsum += w[j];
    }
  if (n < 2) return kNaN;
  const bool equal = mode == ProfileWeights::Median || !(wsum > 0);
  if (mode == ProfileWeights::Median) {
    centre = 0;
    for (double x : v)
      if (std::isfinite(x)) centre += x;
    centre /= static_cast<double>(n);
  }
  double ss = 0, w2 = 0;
  for (std::size_t j = 0; j < v.size(); ++j) {
    if (!std::isfinite(v[j])) continue;
    const double wj = equal ? 1.0 / static_cast<double>(n) : w[j] / wsum;
    ss += wj * (v[j] - centre) * (v[j] - centre);
    w2 += wj * wj;
  }
  return w2 < 1.0 - 1e-12 ? std::sqrt(ss / (1.0 - w2)) : kNaN;
}

// numpy's default (linear) quantile of sorted values.
double quantileSorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

} // namespace

double polylineLength(const glm::vec3* points, std::size_t count) {
  double length = 0;
  for (std::size_t i = 1; i < count; ++i)
    length += glm::distance(glm::dvec3(points[i - 1]), glm::dvec3(points[i]));
  return length;
}

std::vector<glm::dvec3> resampleByArcLength(const glm::vec3* points, std::size_t count, int n) {
  std::vector<glm::dvec3> out;
  if (count < 2 || n < 2) return out;
  std::vector<double> along(count, 0.0);
  for (std::size_t i = 1; i < count; ++i)
    along[i] = along[i - 1] + glm::distance(glm::dvec3(points[i - 1]), glm::dvec3(points[i]));
  const double length = along.back();
  out.reserve(static_cast<std::size_t>(n));
  std::size_t seg = 1;
  for (int k = 0; k < n; ++k) {
    const double s = length * static_cast<double>(k) / static_cast<double>(n - 1);
    while (seg < count - 1 && along[seg] < s)
      ++seg;
    const double span = along[seg] - along[seg - 1];
    const double t = span > 0 ? std::clamp((s - along[seg - 1]) / span, 0.0, 1.0) : 0.0;
    out.push_back(glm::mix(glm::dvec3(points[seg - 1]), glm::dvec3(points[seg]), t));
  }
  out.front() = glm::dvec3(points[0]);
  out.back() = glm::dvec3(points[count - 1]);
  return out;
}

bool fitsBetterReversed(const std::vector<glm::dvec3>& line, const std::vector<glm::dvec3>& reference) {
  double direct = 0, reversed = 0;
  const std::size_t n = std::min(line.size(), reference.size());
  for (std::size_t i = 0; i < n; ++i) {
    direct += glm::distance(line[i], reference[i]);
    reversed += glm::distance(line[line.size() - 1 - i], reference[i]);
  }
  return direct > reversed;
}

double sampleZeroPadded(const ScalarVolume& volume, const glm::dvec3& world) {
  const glm::dvec3 p = volume.grid.toVoxel(world);
  const glm::ivec3 d = volume.grid.dims;
  if (!(p.x > -1 && p.y > -1 && p.z > -1 && p.x < d.x && p.y < d.y && p.z < d.z)) return 0.0;
  const glm::ivec3 base(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)),
                        static_cast<int>(std::floor(p.z)));
  const glm::dvec3 f = p - glm::dvec3(base);
  double sum = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::ivec3 o(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    const glm::ivec3 v = base + o;
    if (!volume.grid.contains(v.x, v.y, v.z)) continue;
    const double weight = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
    if (weight == 0) continue; // a NaN neighbour of weight 0 does not reach the value
    sum += weight * static_cast<double>(volume.at(v.x, v.y, v.z, 0));
  }
  return sum;
}

std::vector<double> nodeWeights(const std::vector<glm::dvec3>& positions, ProfileWeights weights) {
  std::vector<double> w;
  weightsInto(positions.data(), positions.size(), weights, w);
  return w;
}

std::string nodeAxisLabel(const glm::dvec3& first, const glm::dvec3& last) {
  const glm::dvec3 d = last - first;
  const glm::dvec3 a = glm::abs(d);
  static const char* names[3][2] = {{"right", "left"}, {"anterior", "posterior"}, {"superior", "inferior"}};
  const double largest = std::max({a.x, a.y, a.z});
  if (!(largest > 0)) return "start → end";
  // The axes the core travels along, largest first: the dominant one, and any other at least half as long.
  std::vector<int> axes = {0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int p, int q) { return a[p] > a[q]; });
  std::string from, to;
  for (int axis : axes) {
    if (a[axis] < 0.5 * largest) break;
    const bool increasing = d[axis] > 0; // towards R, A or S
    from += (from.empty() ? "" : " ") + std::string(names[axis][increasing ? 1 : 0]);
    to += (to.empty() ? "" : " ") + std::string(names[axis][increasing ? 0 : 1]);
  }
  return from + " → " + to;
}

namespace {

// Whether the profile reverses the streamline of `count` points at `p`: it ends nearer the start point than
// it begins, or (no start point) it fits the reference (the bundle's first profiled streamline, kOrientPoints
// points, set here from the first streamline asked about) better reversed.
bool reversedInProfile(const glm::vec3* p, std::size_t count, const ProfileOptions& o,
                       std::vector<glm::dvec3>& reference) {
  if (o.start)
    return glm::distance(glm::dvec3(p[count - 1]), *o.start) < glm::distance(glm::dvec3(p[0]), *o.start);
  std::vector<glm::dvec3> coarse = resampleByArcLength(p, count, kOrientPoints);
  if (!reference.empty()) return fitsBetterReversed(coarse, reference);
  reference = std::move(coarse);
  return false;
}

bool profiled(const glm::vec3* p, std::size_t count) {
  return count >= 2 && polylineLength(p, count) > 0;
}

} // namespace

std::vector<float> nodePerPoint(const Polylines& lines, const std::vector<std::uint32_t>* which,
                                const ProfileOptions& o) {
  if (o.nodes < 2) throw UsageError("a profile needs at least 2 nodes, not " + std::to_string(o.nodes));
  std::vector<float> out(lines.points.size(), std::numeric_limits<float>::quiet_NaN());
  std::vector<glm::dvec3> reference;
  const auto assign = [&](std::uint32_t idx) {
    if (idx >= lines.lineCount())
      throw InputError("streamline " + std::to_string(idx) + " is named but there are only " +
                       std::to_string(lines.lineCount()));
    const std::size_t b = lines.offsets[idx], e = lines.offsets[idx + 1];
    const glm::vec3* p = lines.points.data() + b;
    if (!profiled(p, e - b)) return;
    const bool flip = reversedInProfile(p, e - b, o, reference);
    const double length = polylineLength(p, e - b), last = o.nodes - 1;
    double along = 0;
    for (std::size_t i = 0; i < e - b; ++i) {
      if (i > 0) along += glm::distance(glm::dvec3(p[i - 1]), glm::dvec3(p[i]));
      const double t = std::clamp(along / length, 0.0, 1.0);
      out[b + i] = static_cast<float>(std::round((flip ? 1.0 - t : t) * last));
    }
  };
  if (which)
    for (std::uint32_t idx : *which)
      assign(idx);
  else
    for (std::uint32_t idx = 0; idx < lines.lineCount(); ++idx)
      assign(idx);
  return out;
}

BundleProfile profileBundle(const Polylines& lines, const std::vector<std::uint32_t>* which,
                            const std::vector<ProfileScalar>& scalars, const ProfileOptions& o) {
  if (o.nodes < 2) throw UsageError("a profile needs at least 2 nodes, not " + std::to_string(o.nodes));
  if (!(o.confidence > 0 && o.confidence < 1)) throw UsageError("the confidence level must lie in (0, 1)");
  for (const auto& s : scalars)
    if (!s.volume || s.volume->data.empty()) throw InputError("scalar '" + s.name + "' has no image");
  const std::size_t lineCount = lines.lineCount();
  std::vector<std::uint32_t> all;
  if (!which) {
    all.resize(lineCount);
    std::iota(all.begin(), all.end(), 0u);
    which = &all;
  }
  const int N = o.nodes;
  const auto Nz = static_cast<std::size_t>(N);
  BundleProfile r;
  std::vector<glm::dvec3> nodes; // streamline-major: nodes[j * N + k]
  nodes.reserve(which->size() * Nz);
  std::vector<glm::dvec3> reference;
  for (const std::uint32_t idx : *which) {
    if (idx >= lineCount)
      throw InputError("streamline " + std::to_string(idx) + " is named but there are only " +
                       std::to_string(lineCount));
    const std::size_t b = lines.offsets[idx], e = lines.offsets[idx + 1];
    const glm::vec3* p = lines.points.data() + b;
    if (!profiled(p, e - b)) {
      ++r.skipped;
      continue;
    }
    std::vector<glm::dvec3> res = resampleByArcLength(p, e - b, N);
    if (reversedInProfile(p, e - b, o, reference)) {
      std::reverse(res.begin(), res.end());
      ++r.flipped;
    }
    nodes.insert(nodes.end(), res.begin(), res.end());
  }
  const std::size_t n = nodes.size() / Nz;
  r.streamlines = n;
  if (n == 0)
    throw InputError(which->empty() ? "the bundle has no streamlines"
                                    : "none of the bundle's " + std::to_string(which->size()) +
                                          " streamlines has two distinct points");

  // Node-major from here: byNode[k * n + j] and values[s][k * n + j], so that a node's positions and values
  // (gathered again for every bootstrap draw) lie together in memory.
  std::vector<glm::dvec3> byNode(n * Nz);
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t k = 0; k < Nz; ++k)
      byNode[k * n + j] = nodes[j * Nz + k];
  nodes = {};
  std::vector<std::vector<double>> values(scalars.size(), std::vector<double>(n * Nz));
  for (std::size_t s = 0; s < scalars.size(); ++s)
    for (std::size_t i = 0; i < n * Nz; ++i)
      values[s][i] = sampleZeroPadded(*scalars[s].volume, byNode[i]);

  r.core.resize(Nz);
  r.scalars.resize(scalars.size());
  for (std::size_t s = 0; s < scalars.size(); ++s) {
    ScalarProfile& sp = r.scalars[s];
    sp.name = scalars[s].name;
    sp.mean.assign(Nz, kNaN);
    sp.sd.assign(Nz, kNaN);
    sp.ciLow.assign(Nz, kNaN);
    sp.ciHigh.assign(Nz, kNaN);
    sp.streamlines.assign(Nz, 0);
  }
  {
    std::vector<double> w, v(n), scratch;
    for (std::size_t k = 0; k < Nz; ++k) {
      const glm::dvec3* pos = byNode.data() + k * n;
      weightsInto(pos, n, o.weights, w);
      glm::dvec3 core(0.0);
      for (std::size_t j = 0; j < n; ++j)
        core += w[j] * pos[j];
      r.core[k] = core;
      for (std::size_t s = 0; s < scalars.size(); ++s) {
        v.assign(values[s].begin() + static_cast<std::ptrdiff_t>(k * n),
                 values[s].begin() + static_cast<std::ptrdiff_t>((k + 1) * n));
        ScalarProfile& sp = r.scalars[s];
        sp.mean[k] = centreOf(v, w, o.weights, scratch, &sp.streamlines[k]);
        sp.sd[k] = spreadOf(v, w, o.weights, sp.mean[k]);
      }
    }
  }
  if (o.bootstrap <= 0 || scalars.empty()) return r;

  // The bootstrap: resample b draws n streamlines with replacement from a generator seeded by (seed, b), so
  // the draws do not depend on the thread that runs it; weights and centres are recomputed on each draw. The
  // nodes go in chunks whose draws' statistics stay within about 64 MB (each chunk makes the same draws).
  const auto B = static_cast<std::size_t>(o.bootstrap);
  const std::size_t chunk = std::clamp<std::size_t>((std::size_t{8} << 20) / (scalars.size() * B), 1, Nz);
  std::vector<std::vector<double>> boot(scalars.size(),
                                        std::vector<double>(chunk * B)); // [s][(k - k0) * B + b]
  const unsigned threads = static_cast<unsigned>(std::clamp<std::size_t>(
      o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency()),
      1, B));
  const double tail = (1.0 - o.confidence) / 2;
  std::vector<double> sorted;
  for (std::size_t k0 = 0; k0 < Nz; k0 += chunk) {
    const std::size_t k1 = std::min(Nz, k0 + chunk);
    auto work = [&](unsigned t) {
      std::vector<std::size_t> draw(n);
      std::vector<glm::dvec3> pos(n);
      std::vector<double> w, v(n), scratch;
      for (std::size_t b = t; b < B; b += threads) {
        std::uint64_t state = o.seed ^ (0xD1B54A32D192ED03ull * (b + 1));
        for (auto& d : draw)
          d = static_cast<std::size_t>(splitMix(state) % n);
        for (std::size_t k = k0; k < k1; ++k) {
          const glm::dvec3* node = byNode.data() + k * n;
          for (std::size_t j = 0; j < n; ++j)
            pos[j] = node[draw[j]];
          weightsInto(pos.data(), n, o.weights, w);
          for (std::size_t s = 0; s < scalars.size(); ++s) {
            const double* value = values[s].data() + k * n;
            for (std::size_t j = 0; j < n; ++j)
              v[j] = value[draw[j]];
            boot[s][(k - k0) * B + b] = centreOf(v, w, o.weights, scratch);
          }
        }
      }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t)
      pool.emplace_back(work, t);
    work(0);
    for (auto& th : pool)
      th.join();
    for (std::size_t s = 0; s < scalars.size(); ++s)
      for (std::size_t k = k0; k < k1; ++k) {
        sorted.clear();
        for (std::size_t b = 0; b < B; ++b)
          if (const double x = boot[s][(k - k0) * B + b]; std::isfinite(x)) sorted.push_back(x);
        std::sort(sorted.begin(), sorted.end());
        r.scalars[s].ciLow[k] = quantileSorted(sorted, tail);
        r.scalars[s].ciHigh[k] = quantileSorted(sorted, 1 - tail);
      }
  }
  return r;
}

} // namespace dtf::surfaces
