// SPDX-License-Identifier: GPL-3.0-or-later
// The sampling grid of every volume: dimensions, voxel size and the voxel-index -> world RAS mm affine.
// Voxel indices are 0-based (i, j, k) with i fastest in memory; world space is RAS millimetres.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <string>

namespace dtf {

struct Grid {
  glm::ivec3 dims{0};          // voxels along i, j, k
  glm::dvec3 spacing{1.0};     // voxel size in mm along i, j, k (norms of the affine's columns)
  glm::dmat4 voxelToWorld{1.0}; // (i, j, k, 1) -> (x, y, z, 1) world RAS mm; column-major (glm)

  std::size_t voxelCount() const {
    return static_cast<std::size_t>(dims.x) * static_cast<std::size_t>(dims.y) * static_cast<std::size_t>(dims.z);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims.x) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims.y) * k);
  }
  bool contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims.x && j < dims.y && k < dims.z;
  }
  // World RAS mm position of a (possibly fractional) voxel index.
  glm::dvec3 toWorld(const glm::dvec3& ijk) const { return glm::dvec3(voxelToWorld * glm::dvec4(ijk, 1.0)); }
  // Fractional voxel index of a world RAS mm position.
  glm::dvec3 toVoxel(const glm::dvec3& xyz) const;
  // Orthonormal rotation part of the affine (polar decomposition of the 3x3 block); maps voxel-axis
  // directions to world directions. Used to rotate voxel-frame tensors: D_world = R D R^T.
  glm::dmat3 rotation() const;
  // Axis codes such as "LAS": the world direction each voxel axis i, j, k increases towards.
  std::string orientationCode() const;
  // The same dims and a voxel-to-world affine within `toleranceMm` in every entry: two volumes on one grid.
  bool sameAs(const Grid& other, double toleranceMm = 1e-3) const;
  // Axis-aligned world bounds of the voxel centres.
  void worldBounds(glm::dvec3& lo, glm::dvec3& hi) const;
  // Builds a grid from dims, spacing and an affine; spacing is recomputed from the affine's columns.
  static Grid fromAffine(const glm::ivec3& dims, const glm::dmat4& voxelToWorld);
};

} // namespace dtf
