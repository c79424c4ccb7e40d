// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check as the front ends run it (`dtfabric check`, `bench check`, the viewer): loads a DWI
// with its table (validated strictly: the check's answer is a table, so a malformed one is refused rather
// than repaired) or a tensor file, fits once, scores the 24 candidate tables with surfaces::checkOrientation,
// writes the corrected FSL table and draws the contact sheet.
#pragma once

#include "io/model/image.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"
#include "io/formats/tensor_io.h"
#include "surfaces/analyses/orientation_check.h"

#include <string>
#include <vector>

namespace dtf::session {

struct CheckRequest {
  std::string input;
  std::string bval, bvec; // empty: INPUT's sibling files when INPUT is a DWI
  std::string mask;       // empty: the fit's automatic mask (DWI) or every valid voxel (tensor file)
  io::TensorLayout layout = io::TensorLayout::Auto; // tensor files
  bool fibres = false;     // INPUT is a fibre set (ui/session/fibre_input.h: isFibreSet)
  std::string fibreLayout; // fibre sets: auto or a fibre layout name
  std::string tensor;      // fibre sets: a paired tensor whose FA selects the white matter
  surfaces::CheckOptions options;
  int fitThreads = 0; // 0 = hardware concurrency
};

struct CheckRun {
  bool dwi = false;               // a DWI fitted here (the candidates act on its bvec table)
  std::string bvalPath, bvecPath; // DWI only
  std::vector<double> bvals;
  std::vector<glm::dvec3> bvecs; // as written (bvec frame)
  std::string layoutNote;        // tensor files and fibre sets: the layout used and why
  bool fibres = false;           // a fibre set: the first fibres are scored in the file's stored frame
  std::string frameName;         // "bvec" (DWI), "world" (tensor file, world-frame peaks), "voxel", "fsl"
  TensorField field;             // fitted with the given table / as stored, world RAS; fibre sets: the paired
                                 // tensor, else io fibreCarrierField (grid only)
  glm::dmat3 tableToWorld{1.0};  // io::bvecFrameToWorld for a DWI, identity for a tensor file (world frame),
                                 // io::fibreFrameToWorld for a fibre set
  MaskVolume mask;               // the given mask; empty when none
  ScalarVolume meanB0;           // a DWI's mean image at its lowest b-value (the figures' anatomy), else empty
  surfaces::OrientationReport report;
  double loadSeconds = 0, fitSeconds = 0, checkSeconds = 0;
};

// Loads, validates, fits and scores. A fibre set is scored by surfaces::checkFibreOrientation (its first
// fibres; white matter from the paired tensor's FA when given). Throws InputError naming the file and the
// problem: bval/bvec/DWI count mismatch, a diffusion-weighted direction whose norm is off 1 by more than 10%,
// no diffusion-weighted volume, a mask on another grid; UsageError for a bad combination of arguments.
CheckRun runCheck(const CheckRequest& request);

// Writes `bvecs` turned by `m` (column n = m * bvecs[n]) as an FSL 3-row table, atomically; directions that
// are zero or not finite (b=0 rows) are written as given. Throws InputError.
void writeCorrectedBvec(const std::string& path, const std::vector<glm::dvec3>& bvecs,
                        const surfaces::AxisTransform& m);

// The candidates a contact sheet shows: the given table, then the best others by score (at most `count`
// rows in all).
std::vector<std::size_t> sheetRows(const surfaces::OrientationReport& report, std::size_t count = 3);

// Where the contact sheet puts things: a header of `header` pixels, then per row a label strip of `label`
// pixels above three panels of `panel` pixels.
struct SheetLayout {
  int panel = 0, header = 0, label = 0, fontScale = 1;
  int panelTop(int row) const { return header + row * (label + panel) + label; }
};
SheetLayout sheetLayout(int panelPx);

// The contact sheet: one row per entry of `rows` (candidate indices), each the fabric on the axial slice
// through the callosal body, the coronal slice through the corticospinal tracts and the midline sagittal
// slice (chosen from the best candidate), panelPx square each, under a label with the transform and its
// score. Renders with the headless context (`headlessContext`) or the one current on the calling thread (the
// viewer's). Throws GlError.
Image renderContactSheet(const CheckRun& run, const std::vector<std::size_t>& rows, int panelPx = 256,
                         bool headlessContext = true);

} // namespace dtf::session
