// SPDX-License-Identifier: GPL-3.0-or-later
// Tensor, scalar and DWI volumes in and out (NIfTI and the formats of io/formats/formats.h): the first stage of the
// pipeline.
// Readers convert into the canonical TensorField form (world RAS, xx xy xz yy yz zz, mm^2/s; see
// io/model/tensor_field.h); writers convert out of it. Every function here dispatches on the file's format
// (io/formats/formats.h: NIfTI, MRtrix .mif/.mif.gz/.mih, NRRD, FSL dtifit sets, DSI Studio SRC); for NIfTI-1
// and NIfTI-2, .nii and .nii.gz are read;
// the affine is the sform when its code is set, else the qform, else pixdim only. scl_slope/scl_inter
// are applied; integer and float datatypes are converted to float. All functions throw dtf::InputError
// whose message starts with the file name (UsageError for a bad layout name).
#pragma once

#include "io/formats/format_guess.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <functional>
#include <string>
#include <vector>

namespace dtf::io {

// On-disk tensor layouts.
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
  std::string format = "NIfTI"; // "NIfTI", "MRtrix image", "NRRD", "FSL dtifit set", "DSI Studio SRC"
  std::string formatReason;     // why that format was chosen (content, name), shown by `info`
  int niftiVersion = 1;         // 0 for other formats
  std::vector<long long> dims; // dim[1..ndim]
  int datatype = 0;
  std::string datatypeName;
  int intentCode = 0;
  std::string intentName;
  std::string descrip; // dtfabric's tensor writer records the layout here ("dtfabric tensor layout=fsl")
  double sclSlope = 1, sclInter = 0;
  int qformCode = 0, sformCode = 0;
  std::string affineSource;          // "sform", "qform" or "none (pixdim only)"
  Grid grid;                         // spatial dims 1..3 and the chosen voxel -> world RAS mm affine
  std::vector<std::string> warnings; // e.g. sform/qform disagreement, no affine at all
};

struct LoadedTensors {
  TensorField field;
  TensorLayout layout = TensorLayout::Auto;
  std::string layoutReason; // why this layout was chosen (always shown to the user)
  VolumeHeader header;
  std::vector<std::string> warnings; // header warnings plus layout/scale doubts
  std::size_t nanVoxels = 0;         // voxels with NaN/Inf components (stored as invalid)
  std::size_t nonPositiveVoxels = 0; // finite, non-zero voxels with an eigenvalue <= 0
  ScalarVolume meanB0;               // a fitted DWI's mean b=0 image (its lowest-b volumes), else empty
};

// Reads a tensor volume (4D x 6 or 5D SYMMATRIX) into world RAS mm^2/s. `layout` Auto detects it and
// says why in layoutReason: a dtfabric descrip marker, else intent 1005 (SYMMATRIX, or DTI-TK when the
// median trace/3 > 0.01 suggests 1e-3 mm^2/s units), else which volumes form a positive semi-definite
// tensor (FSL vs MRtrix order). An explicit layout overrides detection. NaN/Inf voxels become invalid.
// Throws InputError for unreadable files, absurd sizes, unsupported datatypes or a non-tensor shape.
LoadedTensors readTensorVolume(const std::string& path, TensorLayout layout = TensorLayout::Auto);
// The same for a file whose format was detected already (detectFormat; see io/input.h).
LoadedTensors readTensorVolume(const std::string& path, const FormatGuess& format,
                               TensorLayout layout = TensorLayout::Auto);
// Writes `field` in `layout` as float32 (voxel-frame layouts rotate back out of world space; DTI-TK
// scales to 1e-3 mm^2/s), sform = qform = grid.voxelToWorld (code 1). Atomic: a temporary file renamed
// into place. `niftiVersion` 1 or 2; the name must end in .nii or .nii.gz, or .mif/.mif.gz/.mih for an
// MRtrix image (always MRtrix's own convention: xx yy zz xy xz yz in the world frame; `layout` ignored),
// or .nrrd (gzip, RAS space, 3D-masked-symmetric-matrix, world tensors; `layout` ignored).
// Throws InputError.
void writeTensorVolume(const std::string& path, const TensorField& field, TensorLayout layout,
                       int niftiVersion = 1);

// Any 1D-7D volume as float (scl_slope/inter applied); components = product of dims 4..7, interleaved
// per voxel. Throws InputError.
ScalarVolume readScalarVolume(const std::string& path, VolumeHeader* header = nullptr);
ScalarVolume readScalarVolume(const std::string& path, const FormatGuess& format, VolumeHeader* header = nullptr);
// Writes float32, components as dim4, sform = qform = v.grid.voxelToWorld, `descrip` in the header (at most
// 79 characters; NIfTI only), or as an MRtrix image (.mif/.mif.gz/.mih). Atomic. Throws InputError.
void writeScalarVolume(const std::string& path, const ScalarVolume& v, int niftiVersion = 1,
                       const std::string& descrip = "dtfabric");
// Header only (no voxel data read), with the same checks as the readers. Throws InputError.
VolumeHeader readHeader(const std::string& path);
VolumeHeader readHeader(const std::string& path, const FormatGuess& format);

} // namespace dtf::io
