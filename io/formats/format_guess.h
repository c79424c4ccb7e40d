// SPDX-License-Identifier: GPL-3.0-or-later
// The file formats a volume path can hold and the detector's answer (format and reason): the vocabulary
// that format detection (io/formats/formats.h) returns and the readers (io/formats/tensor_io.h) take, in a
// header of its own below both.
#pragma once

#include <string>

namespace dtf::io {

enum class FileFormat {
  Nifti,        // .nii / .nii.gz (NIfTI-1 or NIfTI-2)
  Mrtrix,       // .mif / .mif.gz / .mih (+ data file)
  Nrrd,         // .nrrd (attached header) / .nhdr (detached)
  DtifitSet,    // FSL dtifit outputs: basename, or any of its _V1.._V3 / _L1.._L3 / _FA / _MD files
  DsiStudioSrc, // DSI Studio .src.gz (raw DWI and b-table, MATLAB v4)
  DsiStudioFib, // DSI Studio .fib.gz (fibre populations and DTI maps, MATLAB v4)
  Afni,         // AFNI +orig/+tlrc .HEAD with .BRIK[.gz]: scalar and vector bricks (tensors not yet)
};

// "NIfTI", "MRtrix image", "NRRD", "FSL dtifit set", "DSI Studio SRC", "DSI Studio FIB", "AFNI dataset".
const char* formatName(FileFormat f);

struct FormatGuess {
  FileFormat format = FileFormat::Nifti;
  std::string reason; // e.g. "content starts with 'mrtrix image'"
};

} // namespace dtf::io
