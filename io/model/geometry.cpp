#include "io/model/geometry.h"

#include <limits>

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

} // namespace dtf
