// Turns a command's INPUT into a tensor field: any tensor file the io layer reads, or a DWI with its
// bval/bvec (fitted with WLS inside an automatic or given mask). Shared by render, surface and the viewer.
#pragma once

#include "io/formats/tensor_io.h"

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

// INPUT's sibling gradient file: dwi.nii.gz -> dwi.bval for ext ".bval".
std::string gradientSibling(const std::string& path, const std::string& ext);

// Loads INPUT. A 4D file whose volume count is not 6 (or any file given --bval/--bvec) is treated as a DWI
// and fitted. Throws InputError/UsageError naming the file.
io::LoadedTensors loadTensorInput(const std::string& path, const TensorInputOptions& options);

} // namespace dtf::session
