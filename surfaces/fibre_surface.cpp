// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/fibre_surface.h"

#include "io/model/error.h"

#include <cmath>
#include <vector>

namespace dtf::surfaces {

namespace {

struct Sample {
  glm::dvec3 dir{0.0};
  double fa = 0;
  bool ok = false;
};

Sample principal(const TensorField& field, const glm::dvec3& world) {
  Sample s;
  glm::dvec3 ijk = field.grid.toVoxel(world);
  if (!field.grid.contains(static_cast<int>(std::lround(ijk.x)), static_cast<int>(std::lround(ijk.y)),
                           static_cast<int>(std::lround(ijk.z))))
    return s;
  if (!field.valid[field.grid.index(static_cast<int>(std::lround(ijk.x)), static_cast<int>(std::lround(ijk.y)),
                                    static_cast<int>(std::lround(ijk.z)))])
    return s;
  SymTensor t = field.sample(ijk);
  if (t.isZero() || !t.isFinite()) return s;
  EigenSystem e = eigenDecompose(t);
  s.dir = e.vectors[0];
  s.fa = fractionalAnisotropy(e.values);
  s.ok = true;
  return s;
}

// e1 at `p`, flipped to agree with `ref`; false when outside the data or below the FA stop.
bool direction(const TensorField& f, const glm::dvec3& p, const glm::dvec3& ref, double faStop, glm::dvec3& out) {
  Sample s = principal(f, p);
  if (!s.ok || s.fa < faStop) return false;
  out = glm::dot(s.dir, ref) < 0 ? -s.dir : s.dir;
  return true;
}

// One RK4 step along the sign-continuous e1 field. Returns false where tracing must stop.
bool rk4(const TensorField& f, glm::dvec3& p, glm::dvec3& heading, const FibreSurfaceOptions& o, double cosMax) {
  glm::dvec3 k1, k2, k3, k4;
  const double h = o.stepMm;
  if (!direction(f, p, heading, o.faStop, k1)) return false;
  if (!direction(f, p + 0.5 * h * k1, k1, o.faStop, k2)) return false;
  if (!direction(f, p + 0.5 * h * k2, k2, o.faStop, k3)) return false;
  if (!direction(f, p + h * k3, k3, o.faStop, k4)) return false;
  glm::dvec3 d = k1 + 2.0 * k2 + 2.0 * k3 + k4;
  double l = glm::length(d);
  if (!(l > 0)) return false;
  d /= l;
  if (glm::dot(d, heading) < cosMax) return false;
  p += h * d;
  heading = d;
  return true;
}

} // namespace

Mesh fibreSurfaceFromLine(const TensorField& field, const glm::dvec3& a, const glm::dvec3& b,
                          const FibreSurfaceOptions& o) {
  if (!(o.stepMm > 0) || !(o.seedSpacingMm > 0) || !(o.maxLengthMm > 0))
    throw UsageError("fibre surface step, seed spacing and length must be positive");
  const double len = glm::length(b - a);
  if (!(len > 0)) throw UsageError("fibre surface seed line has zero length");
  const int nSeeds = std::max(2, static_cast<int>(std::ceil(len / o.seedSpacingMm)) + 1);
  if (nSeeds > 100000) throw UsageError("fibre surface seed line is too long for its spacing");
  const int maxSteps = static_cast<int>(std::ceil(o.maxLengthMm / o.stepMm));
  const double cosMax = std::cos(o.maxAngleDeg * M_PI / 180.0);
  const double maxGap = o.maxGapFactor * std::max(o.seedSpacingMm, o.stepMm);

  // Seed particles with e1 oriented consistently along the line.
  std::vector<glm::dvec3> seeds(nSeeds), headings(nSeeds);
  std::vector<bool> alive(nSeeds, false);
  glm::dvec3 ref(0.0);
  int valid = 0;
  for (int i = 0; i < nSeeds; ++i) {
    seeds[i] = a + (b - a) * (static_cast<double>(i) / (nSeeds - 1));
    Sample s = principal(field, seeds[i]);
    if (!s.ok || s.fa < o.faStop) continue;
    if (glm::length(ref) == 0) ref = s.dir;
    headings[i] = glm::dot(s.dir, ref) < 0 ? -s.dir : s.dir;
    ref = headings[i];
    alive[i] = true;
    ++valid;
  }
  if (valid < 2) throw InputError("fibre surface seed line lies outside the data or below the FA stop");

  Mesh m;
  std::vector<std::int64_t> seedVertex(nSeeds, -1);
  for (int i = 0; i < nSeeds; ++i)
    if (alive[i]) {
      seedVertex[i] = static_cast<std::int64_t>(m.positions.size());
      m.positions.push_back(glm::vec3(seeds[i]));
    }

  for (double sign : {1.0, -1.0}) {
    std::vector<glm::dvec3> pos = seeds;
    std::vector<glm::dvec3> head(nSeeds);
    for (int i = 0; i < nSeeds; ++i) head[i] = sign * headings[i];
    std::vector<bool> live = alive;
    std::vector<std::int64_t> prev = seedVertex;
    for (int step = 0; step < maxSteps; ++step) {
      std::vector<std::int64_t> cur(nSeeds, -1);
      bool any = false;
      for (int i = 0; i < nSeeds; ++i) {
        if (!live[i]) continue;
        if (!rk4(field, pos[i], head[i], o, cosMax)) {
          live[i] = false;
          continue;
        }
        cur[i] = static_cast<std::int64_t>(m.positions.size());
        m.positions.push_back(glm::vec3(pos[i]));
        any = true;
      }
      // Stitch the strip between the previous and the current front. Orientation: the +e1 and -e1 sweeps
      // are wound oppositely so that the whole sheet has one consistent side.
      for (int i = 0; i + 1 < nSeeds; ++i) {
        std::int64_t p0 = prev[i], p1 = prev[i + 1], c0 = cur[i], c1 = cur[i + 1];
        auto tri = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
          if (sign > 0) m.indices.insert(m.indices.end(), {static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                                           static_cast<std::uint32_t>(z)});
          else m.indices.insert(m.indices.end(), {static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(z),
                                                  static_cast<std::uint32_t>(y)});
        };
        auto close = [&](std::int64_t x, std::int64_t y) {
          return glm::length(glm::dvec3(m.positions[x] - m.positions[y])) <= maxGap;
        };
        if (p0 >= 0 && p1 >= 0 && c0 >= 0 && c1 >= 0 && close(c0, c1)) {
          tri(p0, p1, c1);
          tri(p0, c1, c0);
        } else if (p0 >= 0 && p1 >= 0 && c0 >= 0 && c1 < 0 && close(p1, c0)) {
          tri(p0, p1, c0); // the right particle stopped: close the strip with one triangle
        } else if (p0 >= 0 && p1 >= 0 && c1 >= 0 && c0 < 0 && close(p0, c1)) {
          tri(p0, p1, c1);
        }
      }
      if (!any) break;
      prev = cur;
    }
  }
  if (m.indices.empty()) throw InputError("fibre surface: no particle could be traced from the seed line");
  // Drop seeds that no triangle uses.
  std::vector<std::int64_t> remap(m.positions.size(), -1);
  std::vector<glm::vec3> pos;
  for (auto& i : m.indices) {
    if (remap[i] < 0) {
      remap[i] = static_cast<std::int64_t>(pos.size());
      pos.push_back(m.positions[i]);
    }
    i = static_cast<std::uint32_t>(remap[i]);
  }
  m.positions = std::move(pos);
  m.computeNormals();
  return m;
}

double fibreCrossingScore(const Mesh& mesh, const TensorField& field, double* weightSum) {
  double num = 0, den = 0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    glm::dvec3 cr = glm::cross(b - a, c - a);
    double area = 0.5 * glm::length(cr);
    if (!(area > 0)) continue;
    glm::dvec3 n = cr / (2 * area);
    Sample s = principal(field, (a + b + c) / 3.0);
    if (!s.ok) continue;
    double w = area * s.fa;
    num += w * std::abs(glm::dot(s.dir, n));
    den += w;
  }
  if (weightSum) *weightSum = den;
  return den > 0 ? num / den : 0.0;
}

} // namespace dtf::surfaces
