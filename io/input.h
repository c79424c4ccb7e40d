// SPDX-License-Identifier: GPL-3.0-or-later
// What an INPUT file is, decided once: a tensor volume, a fibre set, a DWI to fit or a tractogram, with the
// reason, the file format (detected once; the readers below take it rather than detecting it again) and,
// for a DWI, where its gradient table is. Every front end opens its INPUT here, then reads it with the
// reader of its kind, so the rules that tell the kinds apart live in one place.
#pragma once

#include "io/diffusion/dwi.h"
#include "io/formats/fibre_io.h"
#include "io/formats/formats.h"
#include "io/formats/tensor_io.h"

#include <optional>
#include <string>

namespace dtf::io {

enum class InputKind { Tensors, Fibres, Dwi, Tractogram };

// "tensor volume", "fibre set", "DWI", "tractogram".
const char* inputKindName(InputKind kind);

struct InputRequest {
  std::string path;
  std::string layout =
      "auto";               // a tensor layout (auto, fsl, mrtrix, ...) or a fibre layout (mrtrix-peaks, ...)
  std::string bval, bvec;   // a DWI's gradient files; empty: the file's own table, else sibling files
  bool fibres = true;       // a fibre set is a possible answer (false: a fibre-looking file is an error)
  bool tractograms = false; // a tract file name (.tck, .trk[.gz], .trx, .vtk, .vtp) is a possible answer
};

struct OpenedInput {
  std::string path;
  InputKind kind = InputKind::Tensors;
  std::string reason; // why this kind, e.g. "4D with 65 volumes, not 6: a DWI with dwi.bval and dwi.bvec"
  FormatGuess format; // the file's format and why (a folder or a tract file: by name)
  TensorLayout tensorLayout = TensorLayout::Auto; // Tensors: the layout asked for
  FibreLayout fibreLayout = FibreLayout::Auto;    // Fibres: the layout asked for
  std::string bval, bvec;                         // Dwi: the gradient files; empty with embeddedGradients
  bool embeddedGradients = false;                 // Dwi: the table is inside the file (dw_scheme, b_table)
};

// Decides what `request.path` is, in this order:
//   a tract file name, when tractograms are asked for                          -> Tractogram
//   a fibre layout named, or (auto layout) looksLikeFibres                      -> Fibres (when allowed)
//   bval or bvec given (both needed: UsageError otherwise)                      -> Dwi
//   an FSL dtifit set, its basename or a member                                 -> Tensors
//   a DWI with its own gradient table (MRtrix dw_scheme, DSI Studio SRC)        -> Dwi
//   4D with 9..48 volumes in threes that looks like fibres, fibres not allowed  -> InputError
//   4D, not 6 volumes, not SYMMATRIX: a DWI with its sibling .bval/.bvec        -> Dwi (InputError without
//   them) anything else                                                               -> Tensors
// Throws InputError naming the file (unreadable, or a DWI without gradient files), UsageError for a bad
// layout name or half a gradient table.
OpenedInput openInput(const InputRequest& request);
// The first two rules alone: the fibre-set answer for a file of format `format` (detectFormat), or nothing.
std::optional<OpenedInput> openFibreSet(const InputRequest& request, const FormatGuess& format);

// The readers of each kind, with the format found by openInput. Each throws InputError naming the file,
// also when `in` is of another kind (saying what it is instead).
LoadedTensors readInputTensors(const OpenedInput& in);
Dwi readInputDwi(const OpenedInput& in, double b0Threshold = 50.0);
LoadedFibres readInputFibres(const OpenedInput& in);
VolumeHeader readInputHeader(const OpenedInput& in);

// A file's sibling gradient file: dwi.nii.gz -> dwi.bval for ext ".bval".
std::string gradientSibling(const std::string& path, const std::string& ext);

} // namespace dtf::io
