// SPDX-License-Identifier: GPL-3.0-or-later
// Analytic tensor fields for tests and demos (paper section 3.1): synthetic input
// for every stage after the readers. Each phantom is a canonical TensorField (world RAS) on an RAS grid
// centred at the origin, plus a scalar field whose isosurface is the natural surface to render it on.
//   sphere    Hessian of |x| (curvature tensor (I - n n^T)/r, 1/mm; invalid at the centre); scalar |x| mm,
//             isovalue 0.35 x extent.
//   bretzel5  Hessian of f = ((x^2 + y^2/4 - 1)(x^2/4 + y^2 - 1))^2 + z^2 - 0.1 (paper Eq. 14) in closed
//             form, on x, y in [-2.2, 2.2], z in [-1, 1] function units (1/mm^2); scalar f, isovalue 0.
//   constant  prolate tensor, eigenvalues (1.7, 0.3, 0.3)e-3 mm^2/s, along angleDeg/elevationDeg; scalar FA.
//   crossing  two such bundles (bands) crossing at crossingDeg in the axial plane, summed where they
//             overlap; zero and invalid elsewhere; scalar FA.
//   brain     ellipsoidal head: isotropic tissue (MD 1e-3) and a CSF rim (MD 3e-3), a left-right corpus
//             callosum arch, superior-inferior corticospinal columns and anterior-posterior cingula
//             (prolate tensors along the curves); background invalid; scalar FA.
#pragma once

#include "io/model/implicit_functions.h"

#include "io/model/fibre_set.h"

#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <string>
#include <vector>

namespace dtf::io {

// Voxel sizes a phantom may have, in mm: from ex-vivo micro-MRI to coarse; outside them the written
// affine is singular or not finite in float, and no reader (ours included) takes the file back.
constexpr double kMinPhantomSpacingMm = 1e-3, kMaxPhantomSpacingMm = 100.0;

struct PhantomOptions {
  int size = 64;           // voxels per side
  double spacing = 1.0;    // mm
  double angleDeg = 30.0;  // constant: in-plane angle of the principal direction from +x towards +y
  double elevationDeg = 0; // constant: angle out of the axial plane towards +z
  double crossingDeg = 90; // crossing: angle between the two bundles
  bool las = false;        // LAS grid (x index runs towards the patient's left, det(affine) < 0) instead of RAS
};

struct Phantom {
  TensorField tensors;
  ScalarVolume scalar; // sphere/bretzel5: the implicit function; others: FA
  double isovalue = 0; // level of `scalar` that gives the intended surface
};

// Names: sphere, bretzel5, constant, crossing, brain. Throws UsageError for an unknown name, a size outside
// 4..512 or a non-positive spacing.
Phantom makePhantom(const std::string& name, const PhantomOptions& options = {});
std::vector<std::string> phantomNames();

// The fibre set of a phantom (crossing: one fibre per bundle, amplitude 0.7 where a bundle is alone, 0.4 each
// where they overlap, the two listed in alternating order from voxel to voxel so readers and the renderer
// cannot rely on peak order; constant: one fibre along angleDeg/elevationDeg, amplitude 0.7). Same grid as
// makePhantom. Throws UsageError for other names.
FibreSet makeFibrePhantom(const std::string& name, const PhantomOptions& options = {});

// The closed-form Bretzel5 function the phantom samples (io/model/implicit_functions.h).
using dtf::bretzel5;
using dtf::Bretzel5Value;

} // namespace dtf::io
