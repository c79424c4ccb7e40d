// SPDX-License-Identifier: GPL-3.0-or-later
// The canonical in-memory tensor volume. Every reader converts into this form and every writer out of it:
//   * tensors are in WORLD RAS coordinates (already rotated out of any voxel/bvec frame),
//   * components ordered xx, xy, xz, yy, yz, zz (SymTensor),
//   * units mm^2/s (DTI-TK's 1e-3 mm^2/s and similar scalings are undone on read),
//   * the Grid carries the voxel -> world RAS mm affine.
// Voxels without data (outside the mask, NaN on disk) hold a zero tensor and valid = 0.
#pragma once

#include "io/model/grid.h"
#include "io/model/tensor.h"
#include "io/model/volume.h"

#include <vector>

namespace dtf {

struct TensorField {
  Grid grid;
  std::vector<SymTensor> tensors;   // grid.voxelCount() entries
  std::vector<unsigned char> valid; // 1 where the voxel holds a finite, non-zero tensor

  SymTensor& at(int i, int j, int k) { return tensors[grid.index(i, j, k)]; }
  const SymTensor& at(int i, int j, int k) const { return tensors[grid.index(i, j, k)]; }

  // Trilinear interpolation of the tensor components (never of eigenvectors) at a fractional voxel
  // index; zero tensor outside the grid.
  SymTensor sample(const glm::dvec3& ijk) const;
  // Same, at a world RAS mm position.
  SymTensor sampleWorld(const glm::dvec3& xyz) const { return sample(grid.toVoxel(xyz)); }
};

// Creates a zero field on `grid` with all voxels invalid.
TensorField makeTensorField(const Grid& grid);

struct MetricMaps {
  ScalarVolume fa, md, ad, rd, mode;
  Volume<float> dec; // 3 components, RGB in [0, 1]
};

// FA/MD/AD/RD/mode/DEC maps, computed in parallel over slices. Invalid voxels get 0.
MetricMaps computeMetricMaps(const TensorField& field, bool withMode = true, bool withDec = true);
// FA only (the hot path for isosurfaces).
ScalarVolume computeFaMap(const TensorField& field);

} // namespace dtf
