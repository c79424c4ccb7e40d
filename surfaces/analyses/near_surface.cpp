// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/analyses/near_surface.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

namespace dtf::surfaces {

namespace {

// Near flags of line [b, e): distance to the surface <= maxMm.
void nearFlags(const Polylines& lines, std::size_t b, std::size_t e, const DistanceQuery& surface,
               double maxMm, const glm::vec3& boxLo, const glm::vec3& boxHi, bool exhaustive,
               std::vector<char>& near) {
  near.assign(e - b, 0);
  if (exhaustive) {
    for (std::size_t i = b; i < e; ++i)
      near[i - b] = surface.distance(lines.points[i]) <= maxMm;
    return;
  }
  glm::vec3 lo = lines.points[b], hi = lo;
  for (std::size_t i = b + 1; i < e; ++i) {
    lo = glm::min(lo, lines.points[i]);
    hi = glm::max(hi, lines.points[i]);
  }
  if (glm::any(glm::lessThan(hi, boxLo)) || glm::any(glm::greaterThan(lo, boxHi))) return;
  std::uint32_t hint = ~0u; // the triangle found near the previous point: often near this one too
  for (std::size_t i = b; i < e; ++i) {
    const glm::vec3& p = lines.points[i];
    if (glm::any(glm::lessThan(p, boxLo)) || glm::any(glm::greaterThan(p, boxHi))) continue; // > maxMm away
    near[i - b] = surface.within(p, maxMm, &hint);
  }
}

// Appends the runs of >= 2 near points of line [b, e) as lines of `out`.
void appendRuns(const Polylines& lines, std::size_t b, std::size_t e, const std::vector<char>& near,
                Polylines& out) {
  std::size_t i = b;
  while (i < e) {
    if (!near[i - b]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < e && near[j - b])
      ++j;
    if (j - i >= 2) {
      out.appendPoints(lines, i, j);
      out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
    }
    i = j;
  }
}

} // namespace

Polylines selectNearSurface(const Polylines& lines, const DistanceQuery& surface, double maxMm,
                            const NearSurfaceOptions& o) {
  if (maxMm <= 0) return lines;
  glm::vec3 boxLo, boxHi;
  surface.bounds(boxLo, boxHi);
  const glm::vec3 grow(static_cast<float>(maxMm) * 1.0001f + 1e-4f); // never tighter than maxMm in float
  boxLo -= grow;
  boxHi += grow;
  const std::size_t count = lines.lineCount();
  // Contiguous chunks of lines, one output per chunk, joined in order.
  const int hw =
      o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t chunks =
      std::clamp<std::size_t>(count / 64, 1, static_cast<std::size_t>(std::min(hw, 64)) * 4);
  std::vector<Polylines> parts(chunks);
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    std::vector<char> near;
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
      Polylines& part = parts[c];
      part.offsets.assign(1, 0);
      for (std::size_t l = count * c / chunks; l < count * (c + 1) / chunks; ++l) {
        if (o.cancel && o.cancel->load(std::memory_order_relaxed)) return;
        const std::size_t b = lines.offsets[l], e = lines.offsets[l + 1];
        nearFlags(lines, b, e, surface, maxMm, boxLo, boxHi, o.exhaustive, near);
        appendRuns(lines, b, e, near, part);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min<int>(hw, static_cast<int>(chunks)); ++t)
    pool.emplace_back(work);
  work();
  for (auto& t : pool)
    t.join();
  Polylines out;
  out.offsets.push_back(0);
  if (o.cancel && o.cancel->load()) return out;
  std::size_t points = 0;
  for (const auto& p : parts)
    points += p.points.size();
  out.points.reserve(points);
  for (const auto& d : lines.perPoint)
    out.perPoint.push_back({d.name, d.components, {}});
  for (const auto& p : parts) {
    const auto base = static_cast<std::uint32_t>(out.points.size());
    out.appendPoints(p, 0, p.points.size());
    for (std::size_t k = 1; k < p.offsets.size(); ++k)
      out.offsets.push_back(base + p.offsets[k]);
  }
  return out;
}

std::optional<glm::vec4> meshPlane(const Mesh& mesh, double toleranceMm) {
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
        c(mesh.positions[mesh.indices[3 * t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (!(len > 1e-9)) continue; // degenerate triangle: try the next
    const glm::dvec3 u = n / len;
    const double w = -glm::dot(u, a);
    for (const glm::vec3& p : mesh.positions)
      if (std::abs(glm::dot(u, glm::dvec3(p)) + w) > toleranceMm) return std::nullopt;
    return glm::vec4(glm::vec3(u), static_cast<float>(w));
  }
  return std::nullopt;
}

} // namespace dtf::surfaces
