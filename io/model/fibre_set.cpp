// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/fibre_set.h"

#include "io/model/error.h"
#include "io/model/tensor.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dtf {

int FibreSet::count(std::size_t index) const {
  int n = 0;
  const Fibre* f = &fibres[index * static_cast<std::size_t>(maxFibres)];
  while (n < maxFibres && f[n].amplitude > 0.0f)
    ++n;
  return n;
}

std::size_t FibreSet::occupiedVoxels() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < grid.voxelCount(); ++i)
    n += fibres[i * static_cast<std::size_t>(maxFibres)].amplitude > 0.0f;
  return n;
}

float FibreSet::maxAmplitude() const {
  float m = 0.0f;
  for (const Fibre& f : fibres)
    m = std::max(m, f.amplitude);
  return m;
}

FibreSet makeFibreSet(const Grid& grid, int k) {
  if (k < 1 || k > 16)
    throw InputError("a fibre set needs 1 to 16 fibres per voxel, not " + std::to_string(k));
  FibreSet s;
  s.grid = grid;
  s.maxFibres = k;
  s.fibres.assign(grid.voxelCount() * static_cast<std::size_t>(k), Fibre{});
  return s;
}

void normaliseFibres(FibreSet& set) {
  const auto k = static_cast<std::size_t>(set.maxFibres);
  for (std::size_t v = 0; v < set.grid.voxelCount(); ++v) {
    Fibre* f = &set.fibres[v * k];
    for (std::size_t n = 0; n < k; ++n) {
      const float len = glm::length(f[n].direction);
      if (!(f[n].amplitude > 0.0f) || !std::isfinite(f[n].amplitude) || !(len > 1e-12f) ||
          !std::isfinite(len))
        f[n] = Fibre{};
      else
        f[n].direction /= len;
    }
    std::stable_sort(f, f + k, [](const Fibre& a, const Fibre& b) { return a.amplitude > b.amplitude; });
  }
}

TensorField fibreCarrierField(const FibreSet& set) {
  TensorField t = makeTensorField(set.grid);
  const auto k = static_cast<std::size_t>(set.maxFibres);
  for (std::size_t v = 0; v < set.grid.voxelCount(); ++v) {
    const Fibre* f = &set.fibres[v * k];
    if (!(f[0].amplitude > 0.0f)) continue;
    glm::dmat3 m = 1e-4 * glm::dmat3(1.0);
    for (std::size_t n = 0; n < k && f[n].amplitude > 0.0f; ++n) {
      const glm::dvec3 d(f[n].direction);
      m += 1e-3 * glm::outerProduct(d, d) * static_cast<double>(f[n].amplitude / f[0].amplitude);
    }
    t.tensors[v] = SymTensor::fromMat(m);
    t.valid[v] = 1;
  }
  return t;
}

std::vector<Fibre> interpolateFibres(const FibreSet& set, const glm::dvec3& ijk, float relativeThreshold,
                                     int maxOut, float minMatchCos, bool sortByAmplitude) {
  struct Corner {
    double w = 0;
    int n = 0;
    std::array<Fibre, 3> lobes;
  };
  const int kUse = std::clamp(std::min(maxOut, set.maxFibres), 0, 3);
  std::array<Corner, 8> corners;
  const glm::dvec3 base = glm::floor(ijk), frac = ijk - base;
  double valid = 0;
  int ref = -1;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 v = glm::ivec3(base) + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    Corner& k = corners[static_cast<std::size_t>(c)];
    k.w = ((c & 1) ? frac.x : 1 - frac.x) * ((c & 2) ? frac.y : 1 - frac.y) * ((c & 4) ? frac.z : 1 - frac.z);
    if (!set.grid.contains(v.x, v.y, v.z)) continue;
    const Fibre* f = set.at(v.x, v.y, v.z);
    float top = 0.0f;
    for (int n = 0; n < kUse; ++n)
      top = std::max(top, f[n].amplitude);
    // Slots keep their place (absent ones have amplitude 0), so slot j means the same in every voxel.
    for (int n = 0; n < kUse; ++n)
      if (f[n].amplitude > 0.0f && f[n].amplitude >= relativeThreshold * top) {
        k.lobes[static_cast<std::size_t>(n)] = f[n];
        k.n = n + 1;
      }
    if (k.n == 0) continue;
    valid += k.w;
    if (ref < 0 || k.w > corners[static_cast<std::size_t>(ref)].w) ref = c;
  }
  std::vector<Fibre> out;
  if (ref < 0 || valid < 0.5) return out;
  const Corner& r = corners[static_cast<std::size_t>(ref)];
  for (int j = 0; j < kUse; ++j) {
    if (!(r.lobes[static_cast<std::size_t>(j)].amplitude > 0.0f)) {
      if (!sortByAmplitude) out.push_back(Fibre{});
      continue;
    }
    const glm::dvec3 rd(r.lobes[static_cast<std::size_t>(j)].direction);
    glm::dvec3 acc = r.w * r.lobes[static_cast<std::size_t>(j)].amplitude * rd;
    double amp = r.w * r.lobes[static_cast<std::size_t>(j)].amplitude;
    for (int c = 0; c < 8; ++c) {
      const Corner& k = corners[static_cast<std::size_t>(c)];
      if (c == ref || k.n == 0) continue;
      int best = -1;
      double bestCos = 0;
      for (int l = 0; l < k.n; ++l) {
        if (!(k.lobes[static_cast<std::size_t>(l)].amplitude > 0.0f)) continue;
        const double d = glm::dot(glm::dvec3(k.lobes[static_cast<std::size_t>(l)].direction), rd);
        if (best < 0 || std::abs(d) > std::abs(bestCos)) {
          best = l;
          bestCos = d;
        }
      }
      if (std::abs(bestCos) < minMatchCos) continue;
      const Fibre& m = k.lobes[static_cast<std::size_t>(best)];
      // Mutual best only: a lobe that lies closer to another reference lobe belongs to that one (where one
      // bundle ends, its neighbour's single lobe must not bend the crossing bundle towards it).
      bool mutual = true;
      for (int j2 = 0; j2 < r.n && mutual; ++j2)
        mutual = j2 == j || !(r.lobes[static_cast<std::size_t>(j2)].amplitude > 0.0f) ||
                 std::abs(glm::dot(glm::dvec3(r.lobes[static_cast<std::size_t>(j2)].direction),
                                   glm::dvec3(m.direction))) <= std::abs(bestCos);
      if (!mutual) continue;
      acc += k.w * m.amplitude * (bestCos < 0 ? -1.0 : 1.0) * glm::dvec3(m.direction);
      amp += k.w * m.amplitude;
    }
    const double len = glm::length(acc);
    if (!(len > 0)) {
      if (!sortByAmplitude) out.push_back(Fibre{});
      continue;
    }
    out.push_back({glm::vec3(acc / len), static_cast<float>(amp / valid)});
  }
  if (!sortByAmplitude) {
    out.resize(static_cast<std::size_t>(kUse));
    return out;
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Fibre& a, const Fibre& b) { return a.amplitude > b.amplitude; });
  if (static_cast<int>(out.size()) > maxOut) out.resize(static_cast<std::size_t>(std::max(maxOut, 0)));
  return out;
}

FibreSet continuousSlots(const FibreSet& set, float relativeThreshold) {
  const int k = std::min(set.maxFibres, 3);
  FibreSet out = makeFibreSet(set.grid, k);
  // The assignments of up to 3 fibres (indices 0..n-1) to 3 slots: all permutations of the slots.
  static const int kPerms[6][3] = {{0, 1, 2}, {1, 0, 2}, {0, 2, 1}, {2, 0, 1}, {1, 2, 0}, {2, 1, 0}};
  const int perms = k == 1 ? 1 : k == 2 ? 2 : 6;
  const glm::ivec3 d = set.grid.dims;
  for (int z = 0; z < d.z; ++z)
    for (int y = 0; y < d.y; ++y)
      for (int x = 0; x < d.x; ++x) {
        const Fibre* src = set.at(x, y, z);
        Fibre f[3];
        int n = 0;
        float top = 0.0f;
        for (int l = 0; l < k; ++l)
          top = std::max(top, src[l].amplitude);
        for (int l = 0; l < k; ++l)
          if (src[l].amplitude > 0.0f && src[l].amplitude >= relativeThreshold * top) f[n++] = src[l];
        if (n == 0) continue;
        const Fibre* nb[3] = {x > 0 ? out.at(x - 1, y, z) : nullptr, y > 0 ? out.at(x, y - 1, z) : nullptr,
                              z > 0 ? out.at(x, y, z - 1) : nullptr};
        int best = 0;
        double bestScore = -1;
        for (int p = 0; p < perms; ++p) { // with k = 2 only the first two entries of the first two are used
          double score = 0;
          for (const Fibre* q : nb) {
            if (!q) continue;
            for (int l = 0; l < n; ++l) {
              const Fibre& s = q[kPerms[p][l]];
              if (s.amplitude > 0.0f)
                score +=
                    std::abs(glm::dot(s.direction, f[l].direction)) * std::min(s.amplitude, f[l].amplitude);
            }
          }
          if (score > bestScore + 1e-9) {
            bestScore = score;
            best = p;
          }
        }
        Fibre* o = out.at(x, y, z);
        for (int l = 0; l < n; ++l) {
          const int slot = kPerms[best][l];
          double sign = 0;
          for (const Fibre* q : nb)
            if (q && q[slot].amplitude > 0.0f)
              sign += glm::dot(q[slot].direction, f[l].direction) * q[slot].amplitude;
          o[slot] = {sign < 0 ? -f[l].direction : f[l].direction, f[l].amplitude};
        }
      }
  // The scan fixes each sign from the neighbours seen before it; a voxel that had none (where a bundle
  // enters a row) keeps its own. Two sweeps over all six face neighbours flip those to their majority.
  static const int kFaces[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sweep = 0; sweep < 2; ++sweep)
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          Fibre* o = out.at(x, y, z);
          for (int slot = 0; slot < k; ++slot) {
            if (!(o[slot].amplitude > 0.0f)) continue;
            double sign = 0;
            for (const auto& f : kFaces) {
              const int i = x + f[0], j = y + f[1], l = z + f[2];
              if (!set.grid.contains(i, j, l)) continue;
              const Fibre& q = out.at(i, j, l)[slot];
              if (q.amplitude > 0.0f) sign += glm::dot(q.direction, o[slot].direction) * q.amplitude;
            }
            if (sign < 0) o[slot].direction = -o[slot].direction;
          }
        }
  return out;
}

std::vector<Fibre> interpolateSlots(const FibreSet& slotted, const glm::dvec3& ijk) {
  const int k = std::min(slotted.maxFibres, 3);
  std::vector<Fibre> out(static_cast<std::size_t>(k));
  const glm::dvec3 base = glm::floor(ijk), frac = ijk - base;
  double occupied = 0;
  glm::dmat3 dyadic[3] = {glm::dmat3(0.0), glm::dmat3(0.0), glm::dmat3(0.0)};
  glm::dvec3 vec[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  double amp[3] = {0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 v = glm::ivec3(base) + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    if (!slotted.grid.contains(v.x, v.y, v.z)) continue;
    const double w =
        ((c & 1) ? frac.x : 1 - frac.x) * ((c & 2) ? frac.y : 1 - frac.y) * ((c & 4) ? frac.z : 1 - frac.z);
    const Fibre* f = slotted.at(v.x, v.y, v.z);
    bool any = false;
    for (int j = 0; j < k; ++j) {
      if (!(f[j].amplitude > 0.0f)) continue;
      const glm::dvec3 d(f[j].direction);
      const double a = w * static_cast<double>(f[j].amplitude);
      dyadic[j] += a * glm::outerProduct(d, d);
      vec[j] += a * d;
      amp[j] += a;
      any = true;
    }
    occupied += any ? w : 0.0;
  }
  if (occupied < 0.5) return out;
  for (int j = 0; j < k; ++j) {
    if (!(amp[j] > 0)) continue;
    // The principal eigenvector of the interpolated dyadic (sign-free: continuous across sign seams), signed
    // along the interpolated vector where that is not zero, for a stable orientation.
    glm::dvec3 d = eigenDecompose(dyadic[j]).vectors[0];
    if (glm::dot(d, vec[j]) < 0) d = -d;
    out[static_cast<std::size_t>(j)] = {glm::vec3(d), static_cast<float>(amp[j] / occupied)};
  }
  return out;
}

Coherence fibreCoherence(const FibreSet& set, const glm::dmat3& frameChange) {
  static const int kSteps[13][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 0},  {1, -1, 0},
                                    {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}, {1, 1, 1},
                                    {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
  const glm::dmat3 a(set.grid.voxelToWorld);
  glm::dvec3 steps[13];
  for (int s = 0; s < 13; ++s)
    steps[s] = glm::normalize(a * glm::dvec3(kSteps[s][0], kSteps[s][1], kSteps[s][2]));
  Coherence c;
  std::size_t along = 0;
  const glm::ivec3 d = set.grid.dims;
  // Single-fibre voxels only (no second fibre above half the first): crossings and noisy grey matter
  // carry no frame evidence.
  auto first = [&](int i, int j, int k, glm::dvec3& out) {
    const Fibre* fs = set.at(i, j, k);
    const Fibre& f = fs[0];
    if (!(f.amplitude > 0.0f)) return false;
    if (set.maxFibres > 1 && fs[1].amplitude > 0.5f * f.amplitude) return false;
    out = glm::normalize(frameChange * glm::dvec3(f.direction));
    return true;
  };
  for (int k = 0; k < d.z; ++k)
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i) {
        glm::dvec3 u, v;
        if (!first(i, j, k, u)) continue;
        for (int s = 0; s < 13; ++s) {
          const int i2 = i + kSteps[s][0], j2 = j + kSteps[s][1], k2 = k + kSteps[s][2];
          if (!set.grid.contains(i2, j2, k2) || !first(i2, j2, k2, v)) continue;
          ++c.pairs;
          along += std::abs(glm::dot(u, steps[s])) > 0.866 && std::abs(glm::dot(v, steps[s])) > 0.866;
        }
      }
  c.score = c.pairs ? double(along) / double(c.pairs) : 0.0;
  return c;
}

} // namespace dtf
