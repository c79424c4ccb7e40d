// SPDX-License-Identifier: GPL-3.0-or-later
// Planar surfaces for browsing: axial/coronal/sagittal slices through voxel centres and oblique planes,
// triangulated on the voxel lattice in world RAS mm, optionally clipped to the brain.
#pragma once

#include "io/model/geometry.h"
#include "io/model/volume.h"

#include <string>

namespace dtf::surfaces {

enum class SliceAxis { Axial, Coronal, Sagittal };

SliceAxis parseSliceAxis(const std::string& name); // axial|coronal|sagittal, else UsageError
const char* sliceAxisName(SliceAxis a);
// The voxel axis (0 = i, 1 = j, 2 = k) whose world direction is closest to the slice normal
// (axial: S, coronal: A, sagittal: R).
int voxelAxisFor(const Grid& grid, SliceAxis axis);
// Number of slices along `axis`.
int sliceCount(const Grid& grid, SliceAxis axis);

struct SliceOptions {
  const ScalarVolume* clip = nullptr; // keep only cells where clip >= clipFloor at all corners (nullptr = whole plane)
  float clipFloor = 0.5f;
  // Keep a cell when ANY corner passes: the mesh then also holds the cells the clip field's clipFloor
  // contour crosses, where a renderer draws a smooth sub-voxel edge (slices: the bilinear contour lies in
  // them exactly; planes: in the cells of their sampling step).
  bool anyCorner = false;
};

// A slice through voxel centres at `index` along the voxel axis of `axis`. Throws InputError if the index
// is outside the grid. Normals face the positive world direction of the axis (S, A or R).
Mesh makeSlice(const Grid& grid, SliceAxis axis, int index, const SliceOptions& options = {});
// An oblique plane through `point` (world mm) with `normal`, sampled every `stepMm`, clipped to the grid's
// bounds (and to options.clip). Empty if the plane misses the grid.
Mesh makePlane(const Grid& grid, const glm::dvec3& point, const glm::dvec3& normal, double stepMm,
               const SliceOptions& options = {});

} // namespace dtf::surfaces
