// SPDX-License-Identifier: GPL-3.0-or-later
// Which file format a volume path holds, found from its content first and its name second. The readers in
// io/formats/tensor_io.h (readHeader, readScalarVolume, readTensorVolume) and readDwi dispatch through this, so
// every command opens NIfTI, MRtrix images, NRRD, FSL dtifit eigen-systems and DSI Studio SRC files the
// same way. The chosen format and the reason are kept on VolumeHeader (format, formatReason).
#pragma once

#include "io/formats/format_guess.h"

#include <string>

namespace dtf::io {

// Detects the format of `path`: the magic bytes ("mrtrix image", "NRRD000", a NIfTI sizeof_hdr, a MATLAB
// v4 matrix header; gzip streams are inflated to look), then the name. A path that does not exist is
// a dtifit basename when <path>_V1/_L1 files exist (members are NIfTI files: see dtifitSetOf). Never throws;
// an unreadable file is reported as NIfTI by name so that the NIfTI reader gives its error.
FormatGuess detectFormat(const std::string& path);

// True when `path` is a DWI whose gradient table is stored inside the file (an MRtrix image with a
// dw_scheme entry, a DSI Studio SRC): then no bval/bvec files are needed. Never throws.
bool hasEmbeddedGradients(const std::string& path);
bool hasEmbeddedGradients(const std::string& path, const FormatGuess& format);

// The basename of the FSL dtifit set `path` names (the basename itself, or a member such as dti_V1.nii.gz
// or dti_FA.nii.gz whose set has _V1 or _L1 files), or "" when it names none. readTensorVolume reads such
// a member as its whole set. Never throws.
std::string dtifitSetOf(const std::string& path);

// True when `path` names an FSL dtifit set (its basename or any member file) that holds all of V1-V3 and
// L1-L3, so readTensorVolume reads it (from any of its files) as the set's tensor. Never throws.
bool isDtifitTensorSet(const std::string& path);

// True when a tensor or scalar writer accepts the output name: .nii, .nii.gz, .mif, .mif.gz, .mih.
bool isWritableVolumeName(const std::string& path);
// The same for tensor writers, which also write .nrrd.
bool isWritableTensorName(const std::string& path);

} // namespace dtf::io
