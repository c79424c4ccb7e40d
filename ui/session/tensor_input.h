// SPDX-License-Identifier: GPL-3.0-or-later
// Turns a command's INPUT, opened by io::openInput (io/input.h), into a tensor field: any tensor file the io
// layer reads, or a DWI with its bval/bvec (fitted with WLS inside an automatic or given mask). Shared by
// render, surface and the viewer.
#pragma once

#include "io/input.h"

#include <functional>
#include <string>

namespace dtf::session {

struct TensorInputOptions {
  io::TensorLayout layout = io::TensorLayout::Auto;
  std::string bval, bvec; // DWI gradient files; when empty, INPUT's sibling .bval/.bvec are used if present
  std::string mask;       // DWI fit mask (NIfTI); empty = automatic
  bool quiet = false;     // no progress/notes on stderr
  // Called from the loading thread with what it is doing, e.g. "fitting tensors to dwi.nii.gz: 40%".
  std::function<void(const std::string&)> onStage;
};

// The opener's request for INPUT with these options: `layoutText` (a tensor or fibre layout name), the
// gradient files, and whether a fibre set is an answer.
io::InputRequest inputRequest(const std::string& path, const std::string& layoutText,
                              const TensorInputOptions& options, bool fibres);

// The tensors of an opened tensor file (read in options.layout) or DWI (fitted). Throws InputError for
// another kind, naming what it is.
io::LoadedTensors loadTensors(const io::OpenedInput& input, const TensorInputOptions& options);

// Opens INPUT as tensors or a DWI (io::openInput, no fibre sets) and loads it. A 4D file whose volume count
// is not 6 (or any file given --bval/--bvec) is treated as a DWI and fitted. Throws InputError/UsageError
// naming the file.
io::LoadedTensors loadTensorInput(const std::string& path, const TensorInputOptions& options);

// The mean of a DWI's volumes at its lowest b-value (b=0 when there are any, within 50 s/mm^2 of it): the
// anatomy shown beneath the fabric. Empty when the b-values do not match the volumes.
ScalarVolume meanLowestB(const io::Dwi& dwi);

} // namespace dtf::session
