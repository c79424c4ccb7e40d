#include "app/render_split.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace dtf::app {

Polylines selectNearSurface(const Polylines& lines, const surfaces::DistanceQuery& surface, double maxMm) {
  if (maxMm <= 0) return lines;
  Polylines out;
  out.offsets.push_back(0);
  std::vector<char> near;
  for (std::size_t l = 0; l < lines.lineCount(); ++l) {
    const std::size_t b = lines.offsets[l], e = lines.offsets[l + 1];
    near.assign(e - b, 0);
    for (std::size_t i = b; i < e; ++i) near[i - b] = surface.distance(lines.points[i]) <= maxMm;
    // Runs of points whose consecutive pairs are kept segments, i.e. runs of near points of length >= 2.
    std::size_t i = b;
    while (i < e) {
      if (!near[i - b]) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < e && near[j - b]) ++j;
      if (j - i >= 2) {
        out.points.insert(out.points.end(), lines.points.begin() + static_cast<std::ptrdiff_t>(i),
                          lines.points.begin() + static_cast<std::ptrdiff_t>(j));
        out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
      }
      i = j;
    }
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

SplitMode parseSplitMode(const std::string& text) {
  SplitMode m;
  if (text == "tracts") m.kind = SplitMode::Kind::Tracts;
  else if (text == "colour" || text == "color") m.kind = SplitMode::Kind::Colour;
  else if (text.rfind("surface=", 0) == 0 && text.size() > 8) m = {SplitMode::Kind::Surface, text.substr(8)};
  else if (text.rfind("input=", 0) == 0 && text.size() > 6) m = {SplitMode::Kind::Input, text.substr(6)};
  else throw UsageError("--split must be tracts, colour, surface=SPEC or input=FILE, not '" + text + "'");
  return m;
}

Image sideBySide(const Image& left, const Image& right) {
  if (left.height != right.height) throw Error("sideBySide: panes of different heights");
  Image out(left.width + right.width, left.height);
  const std::size_t ls = static_cast<std::size_t>(left.width) * 4;
  const std::size_t rs = static_cast<std::size_t>(right.width) * 4;
  for (int y = 0; y < out.height; ++y) {
    std::memcpy(out.pixel(0, y), left.pixel(0, y), ls);
    std::memcpy(out.pixel(left.width, y), right.pixel(0, y), rs);
  }
  return out;
}

} // namespace dtf::app
