// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace dtf {

void Mesh::computeNormals() {
  normals.assign(positions.size(), glm::vec3(0));
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::vec3& a = positions[indices[t]];
    const glm::vec3& b = positions[indices[t + 1]];
    const glm::vec3& c = positions[indices[t + 2]];
    glm::vec3 n = glm::cross(b - a, c - a); // length = 2 * area
    normals[indices[t]] += n;
    normals[indices[t + 1]] += n;
    normals[indices[t + 2]] += n;
  }
  for (auto& n : normals) {
    float l = glm::length(n);
    n = l > 0 ? n / l : glm::vec3(0, 0, 1);
  }
}

void Mesh::bounds(glm::vec3& lo, glm::vec3& hi) const {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = glm::vec3(std::numeric_limits<float>::lowest());
  for (const auto& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
}

namespace {

// Every directed edge a->b (canonical vertex ids) must occur once, and b->a once: closed, consistently
// oriented, no edge shared by more than two triangles. Degenerate triangles fail the test.
bool edgesPaired(const std::vector<std::uint32_t>& indices, const std::vector<std::uint32_t>& canonical,
                 std::size_t vertexCount) {
  std::vector<std::uint32_t> start(vertexCount + 1, 0);
  const std::size_t tris = indices.size() / 3;
  for (std::size_t t = 0; t < tris; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = canonical[indices[3 * t + k]], b = canonical[indices[3 * t + (k + 1) % 3]];
      if (a == b) return false;
      ++start[a + 1];
    }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1), target(indices.size());
  for (std::size_t t = 0; t < tris; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = canonical[indices[3 * t + k]], b = canonical[indices[3 * t + (k + 1) % 3]];
      target[next[a]++] = b;
    }
  auto count = [&](std::uint32_t from, std::uint32_t to) {
    return std::count(target.begin() + start[from], target.begin() + start[from + 1], to);
  };
  for (std::uint32_t a = 0; a < vertexCount; ++a)
    for (std::uint32_t e = start[a]; e < start[a + 1]; ++e)
      if (count(a, target[e]) != 1 || count(target[e], a) != 1) return false;
  return true;
}

} // namespace

bool Mesh::isClosedOutward() const {
  if (indices.empty() || indices.size() % 3 != 0) return false;
  for (std::uint32_t i : indices)
    if (i >= positions.size()) return false;
  // Shared vertices first; if that fails, weld vertices within 2^-20 of the mesh's extent of each other
  // (UV-sphere seams and poles, per-face vertices) and check again. Welding can only close cracks far
  // below a pixel; vertices it fails to weld leave the mesh "open", the safe answer.
  std::vector<std::uint32_t> canonical(positions.size());
  std::iota(canonical.begin(), canonical.end(), 0u);
  if (!edgesPaired(indices, canonical, positions.size())) {
    glm::vec3 lo, hi;
    bounds(lo, hi);
    const double cell = std::max(double(glm::length(hi - lo)), 1e-30) / (1 << 20);
    std::vector<std::array<std::int64_t, 3>> keys(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
      for (int c = 0; c < 3; ++c) keys[i][c] = std::llround((double(positions[i][c]) - lo[c]) / cell);
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    for (std::size_t i = 1; i < order.size(); ++i)
      if (keys[order[i]] == keys[order[i - 1]]) canonical[order[i]] = canonical[order[i - 1]];
    if (!edgesPaired(indices, canonical, positions.size())) return false;
  }
  double volume = 0; // 6 x signed volume
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    volume += glm::dot(glm::dvec3(positions[indices[t]]),
                       glm::cross(glm::dvec3(positions[indices[t + 1]]), glm::dvec3(positions[indices[t + 2]])));
  return volume > 0;
}

std::string Polylines::inconsistency() const {
  if (offsets.empty()) {
    if (!points.empty()) return "points without offsets";
  } else {
    if (offsets.front() != 0) return "the first offset is not 0";
    if (offsets.back() != points.size()) return "the last offset is not the point count";
    for (std::size_t i = 1; i < offsets.size(); ++i)
      if (offsets[i] < offsets[i - 1]) return "offsets decrease at line " + std::to_string(i - 1);
  }
  for (const auto& d : perLine)
    if (d.components < 1 || d.values.size() != lineCount() * static_cast<std::size_t>(d.components))
      return "per-streamline data '" + d.name + "' does not hold one entry per streamline";
  for (const auto& d : perPoint)
    if (d.components < 1 || d.values.size() != points.size() * static_cast<std::size_t>(d.components))
      return "per-point data '" + d.name + "' does not hold one entry per point";
  for (const auto& g : groups)
    for (std::uint32_t l : g.lines)
      if (l >= lineCount())
        return "group '" + g.name + "' names streamline " + std::to_string(l) + " of " +
               std::to_string(lineCount());
  return {};
}

Polylines Polylines::subset(const std::vector<std::uint32_t>& lines) const {
  Polylines out;
  out.offsets.reserve(lines.size() + 1);
  out.offsets.push_back(0);
  for (const auto& d : perLine)
    out.perLine.push_back({d.name, d.components, {}});
  for (const auto& d : perPoint)
    out.perPoint.push_back({d.name, d.components, {}});
  for (std::uint32_t l : lines) {
    if (l >= lineCount()) continue;
    out.appendPoints(*this, offsets[l], offsets[l + 1]);
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
    for (std::size_t k = 0; k < perLine.size(); ++k) {
      const std::size_t c = static_cast<std::size_t>(perLine[k].components);
      out.perLine[k].values.insert(out.perLine[k].values.end(),
                                   perLine[k].values.begin() + static_cast<long>(l * c),
                                   perLine[k].values.begin() + static_cast<long>((l + 1) * c));
    }
  }
  return out;
}

void Polylines::appendPoints(const Polylines& src, std::size_t begin, std::size_t end) {
  points.insert(points.end(), src.points.begin() + static_cast<std::ptrdiff_t>(begin),
                src.points.begin() + static_cast<std::ptrdiff_t>(end));
  if (perPoint.empty())
    for (const auto& d : src.perPoint)
      perPoint.push_back({d.name, d.components, {}});
  for (std::size_t k = 0; k < src.perPoint.size() && k < perPoint.size(); ++k) {
    const auto c = static_cast<std::ptrdiff_t>(src.perPoint[k].components);
    const auto first = src.perPoint[k].values.begin();
    perPoint[k].values.insert(perPoint[k].values.end(), first + static_cast<std::ptrdiff_t>(begin) * c,
                              first + static_cast<std::ptrdiff_t>(end) * c);
  }
}

std::vector<float> Polylines::valuesPerPoint(const std::string& name) const {
  auto norm = [](const TractValues& d, std::size_t item) {
    const std::size_t c = static_cast<std::size_t>(d.components);
    if (c == 1) return d.values[item];
    double s = 0;
    for (std::size_t k = 0; k < c; ++k)
      s += double(d.values[item * c + k]) * d.values[item * c + k];
    return static_cast<float>(std::sqrt(s));
  };
  std::vector<float> out;
  for (const auto& d : perPoint)
    if (d.name == name) {
      out.resize(points.size());
      for (std::size_t i = 0; i < points.size(); ++i)
        out[i] = norm(d, i);
      return out;
    }
  for (const auto& d : perLine)
    if (d.name == name) {
      out.resize(points.size());
      for (std::size_t l = 0; l < lineCount(); ++l)
        std::fill(out.begin() + offsets[l], out.begin() + offsets[l + 1], norm(d, l));
      return out;
    }
  return out;
}

} // namespace dtf
