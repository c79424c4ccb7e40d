// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic re-orderings of real volumes for tests.
#pragma once

#include "io/model/volume.h"

#include <glm/glm.hpp>

namespace dtf::test {

// The re-strided copy: voxel axis i reversed (LAS -> RAS), the affine adjusted so every voxel keeps its world
// position.
inline ScalarVolume flipI(const ScalarVolume& v) {
  ScalarVolume out = v;
  const Grid& g = v.grid;
  glm::dmat4 flip(1.0);
  flip[0][0] = -1.0;
  flip[3][0] = g.dims.x - 1;
  out.grid = Grid::fromAffine(g.dims, g.voxelToWorld * flip);
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i)
        for (int c = 0; c < v.components; ++c)
          out.at(g.dims.x - 1 - i, j, k, c) = v.at(i, j, k, c);
  return out;
}

} // namespace dtf::test
