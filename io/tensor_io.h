// NIfTI tensor, scalar and DWI volumes in and out. Readers convert into the canonical TensorField form
// (world RAS, xx xy xz yy yz zz, mm^2/s; see io/model/tensor_field.h); writers convert out of it.
// All functions throw dtf::InputError naming the file and the problem.
#pragma once

#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <functional>
#include <string>
#include <vector>

namespace dtf::io {

// On-disk tensor layouts (DESIGN.md section 2).
enum class TensorLayout {
  Auto,      // detect from intent code, then from which volumes hold the positive diagonal, then scale
  Fsl,       // 4D x6: xx xy xz yy yz zz, voxel frame (x flipped when det(affine) > 0)
  Mrtrix,    // 4D x6: xx yy zz xy xz yz, world frame
  Symmatrix, // 5D, intent 1005, dim5 = 6: lower triangle row-wise xx xy yy xz yz zz, voxel frame
  Dtitk,     // as Symmatrix, values in 1e-3 mm^2/s
};

const char* layoutName(TensorLayout l);
// Parses fsl|mrtrix|symmatrix|dtitk|auto; throws UsageError otherwise.
TensorLayout parseLayout(const std::string& name);

// Header facts shown by `dtfabric info`.
struct VolumeHeader {
  std::string path;
  int niftiVersion = 1;
  std::vector<long long> dims; // dim[1..ndim]
  int datatype = 0;
  std::string datatypeName;
  int intentCode = 0;
  std::string intentName;
  double sclSlope = 1, sclInter = 0;
  int qformCode = 0, sformCode = 0;
  std::string affineSource; // "sform", "qform" or "none (pixdim only)"
  Grid grid;
};

struct LoadedTensors {
  TensorField field;
  TensorLayout layout = TensorLayout::Auto;
  std::string layoutReason;          // why this layout was chosen (always shown to the user)
  VolumeHeader header;
  std::vector<std::string> warnings; // e.g. sform/qform disagreement
  std::size_t nanVoxels = 0;         // voxels with NaN/Inf components (stored as invalid)
  std::size_t nonPositiveVoxels = 0; // finite, non-zero voxels with an eigenvalue <= 0
};

LoadedTensors readTensorVolume(const std::string& path, TensorLayout layout = TensorLayout::Auto);
// Writes `field` in `layout` (voxel-frame layouts rotate back out of world space). Atomic: a temporary
// file renamed into place.
void writeTensorVolume(const std::string& path, const TensorField& field, TensorLayout layout);

// Any 3D or 4D volume as float (scl_slope/inter applied); components = product of dims 4..7.
ScalarVolume readScalarVolume(const std::string& path, VolumeHeader* header = nullptr);
void writeScalarVolume(const std::string& path, const ScalarVolume& v);
// Header only (no voxel data read).
VolumeHeader readHeader(const std::string& path);

} // namespace dtf::io
