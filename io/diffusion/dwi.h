// SPDX-License-Identifier: GPL-3.0-or-later
// Raw diffusion-weighted images with their b-values and gradient directions, and the tensor fit: the
// "DWI + bval/bvec -> fit -> TensorField" branch of the data flow. The fit's output
// is the canonical TensorField (world RAS, xx xy xz yy yz zz, mm^2/s), like every tensor reader's.
//
// Gradient frame. bvec files use FSL's convention: directions are in the image's voxel axes (i, j, k),
// with the i component negated when det(affine) > 0 (FSL stores gradients as for a radiological, LAS-like
// image). readDwi / makeDwi rotate them into world RAS once:
//   g_world = R * F * g_bvec,  R = grid.rotation(),  F = diag(-1, 1, 1) if det(affine) > 0 else identity.
// A tensor fitted against world gradients is then a world tensor, so no rotation is needed afterwards.
#pragma once

#include "io/formats/formats.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace dtf::io {

struct Dwi {
  Volume<float> signal;                   // components = number of volumes (interleaved per voxel)
  std::vector<double> bvals;              // s/mm^2
  std::vector<glm::dvec3> gradientsWorld; // unit directions in world RAS; zero where the bvec had none (b=0)
  std::string path;                       // DWI file (empty for synthetic data)
  std::string bvalPath, bvecPath;
};

// Reads a bval file: whitespace-separated numbers on one or more lines. Throws InputError naming the file
// and line for a non-numeric, negative or non-finite value, or an empty file.
std::vector<double> readBvals(const std::string& path);
// Reads a bvec file in FSL 3xN or Nx3 layout (told apart by shape; 3x3 is read as FSL 3xN). Values are
// returned as written (bvec frame, not normalised; NaN rows kept). Throws InputError naming the file and
// line for non-numeric text or a shape that is neither, and, when expectedCount > 0, for a count mismatch.
std::vector<glm::dvec3> readBvecs(const std::string& path, std::size_t expectedCount = 0);

// Rotation taking bvec-frame directions to world RAS: R * F (see the top of this file).
glm::dmat3 bvecFrameToWorld(const Grid& grid);

// Builds a Dwi from a signal volume (components = volumes) and a gradient table in the bvec frame:
// checks the counts, accepts zero or NaN directions only where b <= b0Threshold (they become zero),
// normalises the others (logWarning when a norm is off 1 by more than 10%) and rotates them into world
// RAS. `dwiName`, `bvalName`, `bvecName` only label error messages. Throws InputError.
Dwi makeDwi(Volume<float> signal, std::vector<double> bvals, const std::vector<glm::dvec3>& bvecs,
            double b0Threshold = 50.0, const std::string& dwiName = "DWI",
            const std::string& bvalName = "bval", const std::string& bvecName = "bvec");

// Reads a 4D DWI (through readScalarVolume) and its gradient table, then as makeDwi. Throws InputError
// naming the file at fault, e.g. both files and both counts when bval and DWI disagree. With both paths
// empty the table stored in the file is used: an MRtrix image's dw_scheme (scanner frame) or a DSI Studio
// SRC's b_table (see io/formats/dsi_studio.h); InputError when the file holds none.
Dwi readDwi(const std::string& dwiPath, const std::string& bvalPath, const std::string& bvecPath,
            double b0Threshold = 50.0);
// The same for a DWI whose format was detected already (detectFormat; see io/input.h).
Dwi readDwi(const std::string& dwiPath, const FormatGuess& format, const std::string& bvalPath,
            const std::string& bvecPath, double b0Threshold = 50.0);

enum class FitMethod { Wls, Ols };

struct FitOptions {
  FitMethod method = FitMethod::Wls;
  double b0Threshold = 50.0; // b-values at or below this count as b=0 (s/mm^2)
  int threads = 0;           // 0 = hardware concurrency
  // Signals below this (zero, negative, NaN) are clamped to it before the logarithm; DIPY's
  // MIN_POSITIVE_SIGNAL, so results match DIPY on voxels with dropped-out signal.
  double minSignal = 1e-4;
};

// What fitTensors did, for reporting.
struct FitStats {
  std::size_t voxelsFitted = 0;       // voxels inside the mask
  std::size_t clampedSignals = 0;     // signal samples raised to minSignal
  std::size_t nonPositiveTensors = 0; // fitted tensors with an eigenvalue <= 0 (kept, still valid)
  std::size_t invalidVoxels = 0;      // in the mask but no signal above minSignal, or a non-finite or zero
                                      // result (stored invalid)
  std::size_t wlsFallbacks = 0;       // WLS normal equations singular: the OLS result was kept
};

using ProgressFn = std::function<void(double fraction)>;

// Fits the log-linear tensor model ln S = ln S0 - b g^T D g (7 unknowns) per voxel inside `mask`
// (automaticMask when null). OLS uses the design pseudo-inverse; WLS is DIPY's two-step fit (weights
// S^2 from the OLS prediction). Volumes at b <= b0Threshold without a direction enter with b = 0; those
// with a direction keep their b and direction. Work is split over axial slices on options.threads
// threads; `progress` is called from the calling thread with the fraction done (an exception it throws
// cancels the fit and propagates). Output: canonical TensorField on the DWI grid (world RAS, mm^2/s),
// invalid outside the mask. Tensors are stored as fitted: non-positive eigenvalues are kept and counted
// in FitStats (DIPY clips them to 0 afterwards; MRtrix keeps them). Throws InputError for fewer
// than 7 volumes, a mask on another grid, or a gradient scheme that cannot determine a tensor.
TensorField fitTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                       const ProgressFn& progress = {}, FitStats* stats = nullptr);

// What automaticMask found: the voxels holding signal (signalMask), how many of them the mask keeps, and
// whether the data was taken to have no background.
struct AutomaticMaskReport {
  std::size_t voxels = 0;       // of the grid
  std::size_t signalVoxels = 0; // holding signal
  std::size_t keptSignal = 0;   // holding signal and in the mask
  std::size_t kept = 0;         // in the mask
  bool noBackground = false;    // at least kNoBackgroundFraction of the voxels hold signal: all kept
};
constexpr double kSignalFraction = 0.1;       // of the 99th percentile: a voxel holding signal
constexpr double kNoBackgroundFraction = 0.9; // of the grid holding signal: data without background

// The voxels holding signal: a finite mean b=0 signal (the lowest-b volumes when no b <= b0Threshold) of at
// least kSignalFraction of its 99th percentile, or a mean diffusion-weighted signal of at least that fraction
// of its own. Air around a head holds noise of a few percent of the tissue's signal; every voxel of a
// phantom or of a crop of tissue holds signal.
MaskVolume signalMask(const Dwi& dwi, double b0Threshold);

// Approximate brain mask, meant for quick looks, not for analysis. Data without background (at least
// kNoBackgroundFraction of the voxels hold signal: a phantom, a crop of tissue) keeps every voxel holding
// signal. Otherwise: the union of Otsu thresholds of the mean b=0 image and of the mean diffusion-weighted
// image, then the largest 6-connected component, then holes filled slice by slice (axial). Scalp and eyes
// can survive on data that is not skull-stripped (Dice 0.94 against MRtrix dwi2mask on the IU Prisma brain).
// `report`, when given, receives the counts.
MaskVolume automaticMask(const Dwi& dwi, double b0Threshold, AutomaticMaskReport* report = nullptr);

// The warning that a fit with the automatic mask prints when the mask drops more than half of the voxels
// holding signal (naming --mask); empty when it does not.
std::string automaticMaskWarning(const AutomaticMaskReport& report);

} // namespace dtf::io
