// SPDX-License-Identifier: GPL-3.0-or-later
// How near each point of space lies to a set of streamlines, as a weight volume the fabric is drawn through
// (`render --fabric-along`): 1 within a distance of the streamlines, 0 beyond, on an axis-aligned voxel grid
// around them, built once on the CPU and uploaded as a 3D texture (render/fabric/fabric_pipeline.h's
// setAlong), so the per-pixel test costs one texture sample and no per-frame CPU work.
// Pure computation on io/model types; reading the tract file is ui/session's.
#pragma once

#include "io/model/geometry.h"
#include "io/model/volume.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dtf::surfaces {

struct TractProximityOptions {
  double mm = 2.0; // the fabric is drawn within this distance of the streamlines (> 0)
  // The grid's voxel edge: clamp(mm / 4, 0.5, 1) mm, coarser when the streamlines' box would need more
  // than maxVoxels voxels.
  std::size_t maxVoxels = std::size_t(8) << 20;
};

struct TractProximity {
  // World axis-aligned grid (voxelToWorld a scale and a translation) over the streamlines' bounding box grown
  // by mm + 2 voxels; component 0 the weight in [0, 1]. Empty (no voxel) when no streamline has a point.
  ScalarVolume weight;
  double voxelMm = 0.0; // the grid's voxel edge
  double mm = 0.0;
  std::size_t points = 0; // streamline points stamped
};

// The weight of each voxel centre: clamp((mm - d) / h + 0.5, 0, 1), d its distance to the streamlines and h
// the voxel edge, so it falls from 1 to 0 over one voxel around the distance mm and trilinear sampling gives
// a smooth contour. d is an exact Euclidean distance transform (Felzenszwalb and Huttenlocher) of the voxels
// the streamlines pass through (each segment is sampled every h / 2): it is the distance to the centre of the
// nearest such voxel, within (sqrt(3) / 2 + 1 / 4) h of the true distance to the polyline. So a point beyond
// mm + 2.2 h of every streamline gets weight 0 and a point within mm - 1.7 h weight 1.
// `lines`: the streamlines used (indices into `tracts`); nullptr: all. Throws InputError when mm is not a
// finite positive number.
TractProximity tractProximity(const Polylines& tracts, const TractProximityOptions& options,
                              const std::vector<std::uint32_t>* lines = nullptr);

} // namespace dtf::surfaces
