// SPDX-License-Identifier: GPL-3.0-or-later
// A scalar or vector volume on a Grid. Components are interleaved per voxel:
// data[grid.index(i,j,k) * components + c]. Used for FA/MD maps, masks, T1 backgrounds and V1 maps.
#pragma once

#include "io/model/grid.h"
#include "io/model/huge_pages.h"

#include <cstddef>
#include <vector>

namespace dtf {

template <typename T> struct Volume {
  Grid grid;
  int components = 1;
  std::vector<T> data;

  Volume() = default;
  Volume(const Grid& g, int comps, T fill = T{}) : grid(g), components(comps) {
    assignAdvised(data, g.voxelCount() * static_cast<std::size_t>(comps), fill);
  }

  T& at(int i, int j, int k, int c = 0) { return data[grid.index(i, j, k) * components + c]; }
  const T& at(int i, int j, int k, int c = 0) const { return data[grid.index(i, j, k) * components + c]; }
};

using ScalarVolume = Volume<float>;
using MaskVolume = Volume<unsigned char>;

// Trilinear sample of component c at a fractional voxel index; outside the grid returns `outside`.
float sampleTrilinear(const ScalarVolume& v, const glm::dvec3& ijk, int c = 0, float outside = 0.0f);

} // namespace dtf
