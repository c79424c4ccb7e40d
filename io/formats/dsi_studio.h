// SPDX-License-Identifier: GPL-3.0-or-later
// DSI Studio's files (MATLAB v4 matrices, usually gzipped): the SRC file (raw DWI + b-table) is read as a
// DWI through readDwi / readScalarVolume (io/formats/formats.h dispatches to it); the FIB file's DTI maps and up to
// three fibre populations per voxel are read here into plain volumes, to become a fibre set later.
//
// Orientation. Neither file stores a spatial transform. DSI Studio keeps its images in LPS voxel order
// (its NIfTI import reorients volumes so that i grows to the left, j to the posterior, k to the superior,
// and flips the b-table with them), and the b-table vectors and the FIB's odf_vertices are in those voxel
// axes. So the grid given here is voxel -> world = diag(-vx, -vy, vz) with the volume's centre at the
// origin (the true scanner position is unknown), and directions map to world as (-x, -y, z). The real
// pair in the tests checks the b-table against the fibres DSI Studio reconstructed from it.
#pragma once

#include "io/model/volume.h"

#include <string>
#include <vector>

namespace dtf::io {

struct DsiStudioFib {
  Grid grid;                             // LPS voxel axes, centred (see above)
  ScalarVolume dtiFa, md, ad, rd;        // empty when the file lacks them (md etc. in DSI Studio's units)
  std::vector<ScalarVolume> fraction;    // fa0..: per-population quantitative anisotropy, 0 = no fibre
  std::vector<Volume<float>> directions; // per population: 3 components, unit world RAS (zero = none)
};

// Reads a .fib / .fib.gz. Throws InputError naming the file for a malformed or truncated file.
DsiStudioFib readDsiStudioFib(const std::string& path);

} // namespace dtf::io
