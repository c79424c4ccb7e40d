// SPDX-License-Identifier: GPL-3.0-or-later
// The surface to show, as written on the command line and in viewer scripts, shared by `dtfabric surface`
// and `dtfabric render --surface`:
//   fa=T                        FA isosurface at T
//   iso=FILE:VALUE              isosurface of a scalar NIfTI volume
//   slice=AXIS[:INDEX]          axial|coronal|sagittal slice (default: the middle), clipped to the data
//   plane=X,Y,Z:NX,NY,NZ        oblique plane through a world point with a normal (mm)
//   fibre=X0,Y0,Z0:X1,Y1,Z1     fibre-following stream surface seeded on a world-space line (mm)
//   fibre-voxel=I0,J0,K0:I1,J1,K1  the same with the seed line in voxel indices
//   mesh=FILE                   a PLY/OBJ/VTK/VTP mesh in world RAS mm
// Several surfaces at once are joined with '+', e.g. slice=axial:22+slice=coronal:40+slice=sagittal:36.
#pragma once

#include "io/model/geometry.h"
#include "io/model/tensor_field.h"
#include "surfaces/isosurface.h"

#include <string>
#include <vector>

namespace dtf::session {

struct SurfaceSpec {
  enum class Kind { Fa, Iso, Slice, Plane, Fibre, Mesh, Combined } kind = Kind::Fa;
  double value = 0.25;            // fa / iso level
  std::string file;               // iso / mesh
  std::string axis = "axial";     // slice
  int index = -1;                 // slice index, -1 = middle
  glm::dvec3 a{0.0}, b{0.0};      // plane point+normal, fibre seed line ends (world mm)
  bool voxelCoords = false;       // fibre-voxel: a, b are voxel indices
  std::string text;               // as given, for messages
  std::vector<SurfaceSpec> parts; // Combined: the joined surfaces
};

struct SurfaceBuildOptions {
  double smoothSigmaVoxels = 0.6; // FA isosurfaces: Gaussian pre-smoothing
  double minComponentFraction = 0.02;
  int meshSmoothIterations = 15;    // FA isosurfaces: windowed-sinc mesh smoothing (0 = none), each vertex
  double maxShiftVoxels = 0.5;      // moved at most this far (voxels; larger shifts clamped)
  surfaces::SmoothingReport* smoothing = nullptr; // receives what the smoothing did (optional)
  double planeStepMm = 0.0;         // oblique planes: 0 = half the smallest voxel size
  bool clipToData = true;           // slices and planes: only where there is tensor data (false: whole grid,
                                    // for a background volume to show around the brain)
  bool dataEdgeCells = false;       // clipped slices and planes also keep the cells the data's edge crosses
                                    // (renderers draw the smooth sub-voxel edge there; exports keep whole
                                    // cells of data only)
  double fibreStepMm = 0.5, fibreLengthMm = 40, fibreFaStop = 0.15, fibreSeedSpacingMm = 0.75;
};

// Parses the syntax above; UsageError naming the problem otherwise.
SurfaceSpec parseSurfaceSpec(const std::string& text);

// Builds the mesh in world RAS mm. `fa` is the field's FA map (computed by the caller once). Throws
// InputError when the surface is empty ("FA threshold 0.95 yields no surface", seed outside the data).
Mesh buildSurface(const SurfaceSpec& spec, const TensorField& field, const ScalarVolume& fa,
                  const SurfaceBuildOptions& options = {});

// A short human description, e.g. "axial slice 20", "FA isosurface at 0.25".
std::string describeSurface(const SurfaceSpec& spec);

} // namespace dtf::session
