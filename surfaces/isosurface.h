// SPDX-License-Identifier: GPL-3.0-or-later
// Scalar isosurfaces (FA, the phantoms' implicit functions) as triangle meshes in world RAS mm, through
// VTK's flying edges (multithreaded) with optional masking, pre-smoothing, closing at the volume border,
// small-component removal and volume-preserving mesh smoothing.
#pragma once

#include "io/model/geometry.h"
#include "io/model/volume.h"

#include <memory>

namespace dtf::surfaces {

// The largest pre-smoothing sigma in voxels: a Gaussian this wide already blurs a brain into a blob; VTK's
// kernel of a huge one does not fit in memory.
inline constexpr double kMaxSmoothSigmaVoxels = 20;

struct IsosurfaceOptions {
  double smoothSigmaVoxels = 0.0;  // Gaussian pre-smoothing of the volume (0 = none, at most
                                   // kMaxSmoothSigmaVoxels); done once per sweeper
  int meshSmoothIterations = 0;    // windowed-sinc smoothing of the mesh (VTK, normalised coordinates, pass
                                   // band 0.1; volume preserving; 0 = none); normals recomputed after
  double maxShiftVoxels = 0.5;     // smoothing moves no vertex further than this (in voxels); larger shifts
                                   // are clamped to it along their direction
  double minComponentFraction = 0; // drop components with fewer triangles than this fraction of the largest
  bool closeAtBorder = true;       // pad with the outside value so surfaces cut by the border are closed
  bool insideIsLow = false;        // the object is where values are BELOW the isovalue (distance fields);
                                   // default: above it (FA). Normals point out of the object either way.
  const MaskVolume* mask = nullptr; // voxels with mask == 0 take the outside value
};

// What the mesh smoothing did: the largest vertex shift it asked for and how many were clamped.
struct SmoothingReport {
  double maxShiftVoxels = 0;   // before clamping
  double meanShiftVoxels = 0;  // after clamping
  std::size_t clamped = 0, vertices = 0;
};

// Holds the prepared (masked, smoothed, padded) volume so that a new isovalue costs one contouring pass:
// the FA threshold slider re-extracts through this.
class IsosurfaceSweeper {
public:
  IsosurfaceSweeper(const ScalarVolume& volume, const IsosurfaceOptions& options = {});
  ~IsosurfaceSweeper();
  IsosurfaceSweeper(IsosurfaceSweeper&&) noexcept;
  IsosurfaceSweeper& operator=(IsosurfaceSweeper&&) noexcept;

  // The isosurface at `isovalue` in world RAS mm. Empty when the level is never crossed. Thread-compatible:
  // one extraction at a time per sweeper.
  // `report` (optional) receives what the mesh smoothing did.
  Mesh extract(double isovalue, SmoothingReport* report = nullptr) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-off extraction of component 0 (same as IsosurfaceSweeper(volume, options).extract(isovalue)).
Mesh extractIsosurface(const ScalarVolume& volume, double isovalue, const IsosurfaceOptions& options = {},
                       SmoothingReport* report = nullptr);

} // namespace dtf::surfaces
