// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/tracking/tracking.h"

#include "surfaces/tracking/tracking_parameters.h"

#include "io/model/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

namespace dtf::surfaces {

namespace {

// SplitMix64 finaliser: a counter-based generator, so draw (seed, i, k) needs no shared state.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
// Uniform in [0, 1): draw k of seed i.
double uniform(std::uint64_t rngSeed, std::uint64_t i, std::uint64_t k) {
  std::uint64_t z = mix(rngSeed ^ mix(i * 16 + k));
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

// Principal eigenvector and FA of the symmetric tensor c = (xx, xy, xz, yy, yz, zz). The same maths as
// eigenDecompose (trigonometric largest eigenvalue l1) but only e1: the null vector of A - l1 I, the
// largest cross product of its rows; FA from invariants, sqrt(3/2 |A - q I|^2 / |A|^2). Near-repeated l1
// falls back to eigenDecompose. About twice as fast as the full decomposition, which dominated tracking.
// False for a zero or non-finite tensor.
bool principal(const double c[6], glm::dvec3& e1, double& fa) {
  const double xx = c[0], xy = c[1], xz = c[2], yy = c[3], yz = c[4], zz = c[5];
  if (!std::isfinite(xx + xy + xz + yy + yz + zz)) return false;
  const double p1 = xy * xy + xz * xz + yz * yz;
  const double norm2 = xx * xx + yy * yy + zz * zz + 2 * p1;
  if (!(norm2 > 0)) return false;
  const double q = (xx + yy + zz) / 3.0;
  const double ax = xx - q, ay = yy - q, az = zz - q;
  const double p2 = ax * ax + ay * ay + az * az + 2 * p1;
  fa = std::min(1.0, std::sqrt(1.5 * p2 / norm2));
  const double p = std::sqrt(p2 / 6.0);
  if (p <= 1e-12 * std::sqrt(norm2)) { // isotropic: no direction (FA is 0, so tracking stops)
    e1 = glm::dvec3(1, 0, 0);
    return true;
  }
  // det((A - qI) / p) / 2, clamped, gives the angle of the largest eigenvalue.
  const double det = ax * (ay * az - yz * yz) - xy * (xy * az - yz * xz) + xz * (xy * yz - ay * xz);
  const double r = std::clamp(det / (2 * p * p * p), -1.0, 1.0);
  const double l1 = q + 2 * p * std::cos(std::acos(r) / 3.0);
  const glm::dvec3 m0(xx - l1, xy, xz), m1(xy, yy - l1, yz), m2(xz, yz, zz - l1);
  glm::dvec3 best = glm::cross(m0, m1);
  double bestLen = glm::dot(best, best);
  for (const glm::dvec3& v : {glm::cross(m0, m2), glm::cross(m1, m2)}) {
    const double l = glm::dot(v, v);
    if (l > bestLen) best = v, bestLen = l;
  }
  if (!(bestLen > 1e-12 * p2 * p2)) { // l1 (nearly) repeated: let the full solver pick a basis
    SymTensor t;
    t.xx = static_cast<float>(xx), t.xy = static_cast<float>(xy), t.xz = static_cast<float>(xz);
    t.yy = static_cast<float>(yy), t.yz = static_cast<float>(yz), t.zz = static_cast<float>(zz);
    e1 = eigenDecompose(t).vectors[0];
    return true;
  }
  e1 = best / std::sqrt(bestLen);
  return true;
}

// Tensor sampling with the world -> voxel inverse computed once and trilinear interpolation done in place
// (the same result as TensorField::sample, zero outside the voxel-centre box).
class Sampler {
public:
  Sampler(const TensorField& f, const TrackingOptions& o)
      : f_(f), o_(o), worldToVoxel_(glm::inverse(f.grid.voxelToWorld)) {
    if (o.mask) maskWorldToVoxel_ = glm::inverse(o.mask->grid.voxelToWorld);
  }

  // e1 (unit, sign arbitrary) and FA at world position p; false outside the data or the stop mask.
  bool eval(const glm::dvec3& p, glm::dvec3& e1, double& fa) const {
    if (o_.mask) {
      glm::dvec3 m = glm::dvec3(maskWorldToVoxel_ * glm::dvec4(p, 1.0));
      int i = static_cast<int>(std::floor(m.x + 0.5)), j = static_cast<int>(std::floor(m.y + 0.5)),
          k = static_cast<int>(std::floor(m.z + 0.5));
      if (!o_.mask->grid.contains(i, j, k) || !o_.mask->at(i, j, k)) return false;
    }
    double c[6];
    if (!sample(glm::dvec3(worldToVoxel_ * glm::dvec4(p, 1.0)), c)) return false;
    return principal(c, e1, fa);
  }
  // e1 at p with its sign matched to `ref`.
  bool direction(const glm::dvec3& p, const glm::dvec3& ref, glm::dvec3& out) const {
    double fa;
    if (!eval(p, out, fa)) return false;
    if (glm::dot(out, ref) < 0) out = -out;
    return true;
  }

private:
  bool sample(const glm::dvec3& v, double c[6]) const {
    const glm::ivec3 d = f_.grid.dims;
    if (!(v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x <= d.x - 1 && v.y <= d.y - 1 && v.z <= d.z - 1))
      return false;
    const int i0 = static_cast<int>(v.x), j0 = static_cast<int>(v.y), k0 = static_cast<int>(v.z);
    const double fx = v.x - i0, fy = v.y - j0, fz = v.z - k0;
    const std::size_t sx = 1, sy = static_cast<std::size_t>(d.x), sz = sy * static_cast<std::size_t>(d.y);
    const std::size_t base = static_cast<std::size_t>(i0) * sx + static_cast<std::size_t>(j0) * sy +
                             static_cast<std::size_t>(k0) * sz;
    const std::size_t di = i0 + 1 < d.x ? sx : 0, dj = j0 + 1 < d.y ? sy : 0, dk = k0 + 1 < d.z ? sz : 0;
    for (int n = 0; n < 6; ++n)
      c[n] = 0;
    bool any = false;
    for (int corner = 0; corner < 8; ++corner) {
      const double w =
          ((corner & 1) ? fx : 1 - fx) * ((corner & 2) ? fy : 1 - fy) * ((corner & 4) ? fz : 1 - fz);
      if (w == 0) continue;
      const SymTensor& t =
          f_.tensors[base + ((corner & 1) ? di : 0) + ((corner & 2) ? dj : 0) + ((corner & 4) ? dk : 0)];
      c[0] += w * t.xx, c[1] += w * t.xy, c[2] += w * t.xz, c[3] += w * t.yy, c[4] += w * t.yz,
          c[5] += w * t.zz;
      any = true;
    }
    return any;
  }

  const TensorField& f_;
  const TrackingOptions& o_;
  glm::dmat4 worldToVoxel_;
  glm::dmat4 maskWorldToVoxel_{1.0};
};

// Follows e1 from `p` along `heading` for at most `maxSteps`, appending the new points (not the start).
// `e1` is the principal direction at `p` (sign arbitrary); each step's end-point evaluation (needed for the
// FA stop) is reused as the next step's first RK4 stage, so RK4 costs 4 tensor evaluations per step and
// Euler 1.
void follow(const Sampler& s, const TrackingOptions& o, glm::dvec3 p, glm::dvec3 heading, glm::dvec3 e1,
            int maxSteps, std::vector<glm::vec3>& out) {
  const double h = o.stepMm, cosMax = std::cos(o.maxAngleDeg * M_PI / 180.0);
  for (int step = 0; step < maxSteps; ++step) {
    glm::dvec3 d = glm::dot(e1, heading) < 0 ? -e1 : e1;
    if (o.rk4) {
      glm::dvec3 k2, k3, k4;
      if (!s.direction(p + 0.5 * h * d, d, k2) || !s.direction(p + 0.5 * h * k2, k2, k3) ||
          !s.direction(p + h * k3, k3, k4))
        return;
      d = d + 2.0 * k2 + 2.0 * k3 + k4;
      double l = glm::length(d);
      if (!(l > 0)) return;
      d /= l;
    }
    if (glm::dot(d, heading) < cosMax) return;
    glm::dvec3 next = p + h * d;
    double fa;
    if (!s.eval(next, e1, fa) || fa < o.faStop) return;
    out.emplace_back(next);
    p = next;
    heading = d;
  }
}

enum class Outcome : unsigned char { Pending, Accepted, BelowFa, TooShort, Refused };

Outcome trackFrom(const Sampler& s, const TrackingOptions& o, const glm::dvec3& seed,
                  std::vector<glm::vec3>& line) {
  line.clear();
  glm::dvec3 e1;
  double fa;
  if (!s.eval(seed, e1, fa) || fa < o.faStop) return Outcome::BelowFa;
  const int maxSteps = static_cast<int>(std::floor(o.maxLengthMm / o.stepMm + 1e-9));
  std::vector<glm::vec3> back;
  follow(s, o, seed, -e1, e1, maxSteps, back);
  line.assign(back.rbegin(), back.rend());
  line.emplace_back(seed);
  follow(s, o, seed, e1, e1, maxSteps - static_cast<int>(back.size()), line);
  const double length = static_cast<double>(line.size() - 1) * o.stepMm;
  if (length + 1e-9 < o.minLengthMm) {
    line.clear();
    return Outcome::TooShort;
  }
  if (o.accept && !o.accept(line.data(), line.size())) {
    line.clear();
    return Outcome::Refused;
  }
  return Outcome::Accepted;
}

int threadCount(const TrackingOptions& o) {
  int n = o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(n, 1, 256);
}

// Tracks seeds [first, first + n) into slots[0 .. n) in parallel; progress/cancel on the calling thread.
// Returns false when cancelled (unfinished slots stay Pending).
bool runBatch(const TensorField& field, const SeedSource& seeds, const TrackingOptions& o,
              std::uint64_t first, std::size_t n, std::vector<std::vector<glm::vec3>>& lines,
              std::vector<Outcome>& outcome, std::size_t doneBefore, std::size_t planned, int nThreads) {
  lines.assign(n, {});
  outcome.assign(n, Outcome::Pending);
  Sampler sampler(field, o);
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::mutex m;
  std::condition_variable cv;
  int finished = 0;
  constexpr std::size_t kChunk = 32;
  auto worker = [&] {
    std::vector<glm::vec3> line;
    for (;;) {
      std::size_t begin = next.fetch_add(kChunk);
      if (begin >= n) break;
      std::size_t end = std::min(n, begin + kChunk);
      for (std::size_t i = begin; i < end; ++i) {
        if (stop.load(std::memory_order_relaxed) || (o.cancel && o.cancel->load(std::memory_order_relaxed))) {
          stop = true;
          break;
        }
        outcome[i] = trackFrom(sampler, o, seeds.at(first + i), line);
        if (outcome[i] == Outcome::Accepted) lines[i] = line;
      }
      done += end - begin;
      if (stop) break;
    }
    std::lock_guard<std::mutex> lk(m);
    ++finished;
    cv.notify_all();
  };
  const int workers =
      static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(nThreads), (n + kChunk - 1) / kChunk));
  std::vector<std::thread> pool;
  for (int t = 0; t < workers; ++t)
    pool.emplace_back(worker);
  {
    std::unique_lock<std::mutex> lk(m);
    while (!cv.wait_for(lk, std::chrono::milliseconds(100), [&] { return finished == workers; }))
      if (o.progress) {
        lk.unlock();
        o.progress(doneBefore + std::min(done.load(), n), planned);
        lk.lock();
      }
  }
  for (auto& t : pool)
    t.join();
  if (o.progress) o.progress(doneBefore + n, planned);
  return !stop && !(o.cancel && o.cancel->load());
}

// Appends the accepted streamlines of a batch (in seed order) to `r`, at most `limit` in total.
void collect(TrackingResult& r, std::uint64_t first, const std::vector<std::vector<glm::vec3>>& lines,
             const std::vector<Outcome>& outcome, std::size_t limit) {
  if (r.lines.offsets.empty()) r.lines.offsets.push_back(0);
  for (std::size_t i = 0; i < outcome.size(); ++i) {
    if (r.lines.lineCount() >= limit) return;
    if (outcome[i] == Outcome::Pending) continue;
    ++r.seedsTried;
    if (outcome[i] == Outcome::BelowFa) ++r.seedsBelowFa;
    if (outcome[i] == Outcome::TooShort) ++r.tooShort;
    if (outcome[i] == Outcome::Refused) ++r.rejectedByRegions;
    if (outcome[i] != Outcome::Accepted) continue;
    r.lines.points.insert(r.lines.points.end(), lines[i].begin(), lines[i].end());
    r.lines.offsets.push_back(static_cast<std::uint32_t>(r.lines.points.size()));
    r.seedIndex.push_back(first + i);
  }
}

std::vector<std::size_t> maskVoxels(const MaskVolume& mask) {
  std::vector<std::size_t> v;
  for (std::size_t i = 0; i < mask.grid.voxelCount(); ++i)
    if (mask.data[i * mask.components]) v.push_back(i);
  return v;
}

glm::dvec3 voxelOf(const Grid& g, std::size_t idx) {
  const std::size_t nx = static_cast<std::size_t>(g.dims.x), ny = static_cast<std::size_t>(g.dims.y);
  return glm::dvec3(static_cast<double>(idx % nx), static_cast<double>((idx / nx) % ny),
                    static_cast<double>(idx / (nx * ny)));
}

} // namespace

void validate(const TrackingParams& p) {
  for (const auto& param : trackingParameters()) param.check(param.get(p));
  if (p.minLengthMm > p.maxLengthMm)
    throw UsageError("min-length " + shortestNumber(p.minLengthMm) + " mm exceeds max-length " +
                     shortestNumber(p.maxLengthMm) + " mm");
  if (p.maxLengthMm / p.stepMm > 1e6) throw UsageError("max-length is more than a million steps");
}

SeedSource seedsFromMask(const MaskVolume& mask, int perVoxel, std::uint64_t rngSeed) {
  auto voxels = std::make_shared<std::vector<std::size_t>>(maskVoxels(mask));
  if (voxels->empty()) throw InputError("the seed mask is empty");
  if (perVoxel < 0) throw UsageError("seeds per voxel must be >= 0");
  SeedSource s;
  const Grid g = mask.grid;
  const std::uint64_t per = static_cast<std::uint64_t>(perVoxel);
  s.count = per * voxels->size();
  s.description = perVoxel > 0 ? std::to_string(perVoxel) + " random seeds in each of " +
                                     std::to_string(voxels->size()) + " mask voxels"
                               : "random seeds in " + std::to_string(voxels->size()) + " mask voxels";
  s.at = [voxels, g, per, rngSeed](std::uint64_t i) {
    std::size_t v =
        per > 0 ? static_cast<std::size_t>(i / per)
                : std::min(voxels->size() - 1, static_cast<std::size_t>(uniform(rngSeed, i, 0) *
                                                                        static_cast<double>(voxels->size())));
    glm::dvec3 ijk = voxelOf(g, (*voxels)[std::min(v, voxels->size() - 1)]);
    ijk += glm::dvec3(uniform(rngSeed, i, 1), uniform(rngSeed, i, 2), uniform(rngSeed, i, 3)) - 0.5;
    return g.toWorld(ijk);
  };
  return s;
}

SeedSource seedsInSphere(const glm::dvec3& centre, double radiusMm, std::uint64_t rngSeed) {
  if (!(radiusMm > 0)) throw UsageError("seed sphere radius must be positive");
  SeedSource s;
  s.description = "random seeds in a sphere of radius " + std::to_string(radiusMm) + " mm";
  s.at = [centre, radiusMm, rngSeed](std::uint64_t i) {
    for (std::uint64_t k = 0; k + 2 < 16; k += 3) { // rejection sampling; P(fail 5 times) = 0.48^5
      glm::dvec3 u(2 * uniform(rngSeed, i, k) - 1, 2 * uniform(rngSeed, i, k + 1) - 1,
                   2 * uniform(rngSeed, i, k + 2) - 1);
      if (glm::dot(u, u) <= 1) return centre + radiusMm * u;
    }
    return centre;
  };
  return s;
}

SeedSource seedsOnSurface(const Mesh& mesh, std::uint64_t rngSeed) {
  auto cdf = std::make_shared<std::vector<double>>();
  double total = 0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    total += 0.5 * glm::length(glm::cross(b - a, c - a));
    cdf->push_back(total);
  }
  if (!(total > 0)) throw InputError("the seed surface has no area");
  SeedSource s;
  s.description = "random seeds on a surface of " + std::to_string(mesh.triangleCount()) + " triangles";
  auto positions = std::make_shared<std::vector<glm::vec3>>(mesh.positions);
  auto indices = std::make_shared<std::vector<std::uint32_t>>(mesh.indices);
  s.at = [cdf, positions, indices, total, rngSeed](std::uint64_t i) {
    double r = uniform(rngSeed, i, 0) * total;
    std::size_t t = static_cast<std::size_t>(std::upper_bound(cdf->begin(), cdf->end(), r) - cdf->begin());
    t = std::min(t, cdf->size() - 1);
    double u = uniform(rngSeed, i, 1), v = uniform(rngSeed, i, 2);
    if (u + v > 1) u = 1 - u, v = 1 - v; // fold into the triangle: uniform barycentric coordinates
    glm::dvec3 a((*positions)[(*indices)[3 * t]]), b((*positions)[(*indices)[3 * t + 1]]),
        c((*positions)[(*indices)[3 * t + 2]]);
    return a + u * (b - a) + v * (c - a);
  };
  return s;
}

SeedSource seedsOnSlice(const TensorField& field, int axis, int index, const MaskVolume* mask,
                        std::uint64_t rngSeed) {
  const Grid& g = field.grid;
  if (axis < 0 || axis > 2 || index < 0 || index >= g.dims[axis])
    throw InputError("seed slice " + std::to_string(index) + " is outside the volume (0.." +
                     std::to_string(axis >= 0 && axis <= 2 ? g.dims[axis] - 1 : 0) + ")");
  auto voxels = std::make_shared<std::vector<glm::dvec3>>();
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        glm::ivec3 v(i, j, k);
        if (v[axis] != index || !field.valid[g.index(i, j, k)]) continue;
        if (mask) {
          glm::dvec3 m = mask->grid.toVoxel(g.toWorld(glm::dvec3(v)));
          glm::ivec3 mi(static_cast<int>(std::lround(m.x)), static_cast<int>(std::lround(m.y)),
                        static_cast<int>(std::lround(m.z)));
          if (!mask->grid.contains(mi.x, mi.y, mi.z) || !mask->at(mi.x, mi.y, mi.z)) continue;
        }
        voxels->push_back(glm::dvec3(v));
      }
  if (voxels->empty()) throw InputError("seed slice " + std::to_string(index) + " holds no valid voxel");
  SeedSource s;
  s.description = "random seeds in " + std::to_string(voxels->size()) + " voxels of slice " +
                  std::to_string(index) + " along voxel axis " + "ijk"[axis];
  const Grid grid = g;
  s.at = [voxels, grid, axis, rngSeed](std::uint64_t i) {
    std::size_t v =
        std::min(voxels->size() - 1,
                 static_cast<std::size_t>(uniform(rngSeed, i, 0) * static_cast<double>(voxels->size())));
    glm::dvec3 ijk = (*voxels)[v];
    for (int a = 0, k = 1; a < 3; ++a)
      if (a != axis) ijk[a] += uniform(rngSeed, i, static_cast<std::uint64_t>(k++)) - 0.5;
    return grid.toWorld(ijk);
  };
  return s;
}

std::vector<glm::vec3> trackOne(const TensorField& field, const glm::dvec3& seed,
                                const TrackingOptions& options) {
  validate(options);
  Sampler s(field, options);
  std::vector<glm::vec3> line;
  trackFrom(s, options, seed, line);
  return line;
}

TrackingResult trackSeeds(const TensorField& field, const SeedSource& seeds, std::uint64_t seedCount,
                          const TrackingOptions& o) {
  validate(o);
  TrackingResult r;
  r.threads = threadCount(o);
  r.lines.offsets.push_back(0);
  constexpr std::uint64_t kBatch = 1 << 15;
  std::vector<std::vector<glm::vec3>> lines;
  std::vector<Outcome> outcome;
  for (std::uint64_t first = 0; first < seedCount; first += kBatch) {
    std::size_t n = static_cast<std::size_t>(std::min(kBatch, seedCount - first));
    bool ok = runBatch(field, seeds, o, first, n, lines, outcome, first, seedCount, r.threads);
    collect(r, first, lines, outcome, static_cast<std::size_t>(-1));
    if (!ok) {
      r.cancelled = true;
      break;
    }
  }
  return r;
}

TrackingResult trackSelect(const TensorField& field, const SeedSource& seeds, std::size_t select,
                           const TrackingOptions& o, std::uint64_t maxSeeds) {
  validate(o);
  TrackingResult r;
  r.threads = threadCount(o);
  r.lines.offsets.push_back(0);
  if (select == 0) return r;
  if (maxSeeds == 0) maxSeeds = 1000 * static_cast<std::uint64_t>(select);
  if (seeds.count > 0) maxSeeds = std::min(maxSeeds, seeds.count);
  std::vector<std::vector<glm::vec3>> lines;
  std::vector<Outcome> outcome;
  std::uint64_t first = 0;
  while (r.lines.lineCount() < select && first < maxSeeds) {
    // Batch size from the acceptance rate so far (the first batch guesses 1 in 2).
    const double rate =
        r.seedsTried > 0 ? std::max(1e-3, static_cast<double>(r.lines.lineCount()) / r.seedsTried) : 0.5;
    const double need = static_cast<double>(select - r.lines.lineCount()) / rate * 1.1 + 256;
    std::size_t n = static_cast<std::size_t>(std::clamp(need, 1024.0, 65536.0));
    n = static_cast<std::size_t>(std::min<std::uint64_t>(n, maxSeeds - first));
    const std::size_t planned = static_cast<std::size_t>(first) + n;
    bool ok = runBatch(field, seeds, o, first, n, lines, outcome, static_cast<std::size_t>(first), planned,
                       r.threads);
    collect(r, first, lines, outcome, select);
    first += n;
    if (!ok) {
      r.cancelled = true;
      break;
    }
  }
  return r;
}

} // namespace dtf::surfaces
