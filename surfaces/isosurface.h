// Scalar isosurfaces (FA, the phantoms' implicit functions) as triangle meshes in world RAS mm, through
// VTK's flying edges with optional pre-smoothing, small-component removal and consistent outward normals.
#pragma once

#include "io/model/geometry.h"
#include "io/model/volume.h"

namespace dtf::surfaces {

struct IsosurfaceOptions {
  double smoothSigmaVoxels = 0.0;   // Gaussian pre-smoothing of the volume (0 = none)
  int meshSmoothIterations = 0;     // windowed-sinc smoothing of the mesh (volume preserving; 0 = none)
  double minComponentFraction = 0;  // drop connected components with fewer triangles than this fraction of the largest
  bool flipNormals = false;         // normals point towards lower values by default; flip for "outward" of a low-valued inside
};

// Extracts the isovalue surface of component 0. Returns an empty mesh when the level is never crossed.
Mesh extractIsosurface(const ScalarVolume& volume, double isovalue, const IsosurfaceOptions& options = {});

} // namespace dtf::surfaces
