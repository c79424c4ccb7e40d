// Analytic tensor fields for tests and demos (paper section 3.1 and DESIGN.md section 4). Each phantom
// also carries a scalar field whose isosurface is the natural surface to render it on.
#pragma once

#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <string>
#include <vector>

namespace dtf::io {

struct PhantomOptions {
  int size = 64;            // voxels per side
  double spacing = 1.0;     // mm
  double angleDeg = 30.0;   // constant: in-plane angle of the principal direction from +x towards +y
  double elevationDeg = 0;  // constant: angle out of the axial plane towards +z
  double crossingDeg = 90;  // crossing: angle between the two bundles
};

struct Phantom {
  TensorField tensors;
  ScalarVolume scalar;  // sphere/bretzel5: the implicit function; others: FA
  double isovalue = 0;  // level of `scalar` that gives the intended surface
};

// Names: sphere, bretzel5, constant, crossing, brain. Throws UsageError for an unknown name.
Phantom makePhantom(const std::string& name, const PhantomOptions& options = {});
std::vector<std::string> phantomNames();

} // namespace dtf::io
