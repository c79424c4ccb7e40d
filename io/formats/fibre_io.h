// SPDX-License-Identifier: GPL-3.0-or-later
// Crossing-fibre files in and out: readers convert into the canonical FibreSet (io/model/fibre_set.h: unit
// world-RAS directions, strongest first), writers convert out of it. Layouts on disk:
//   mrtrix-peaks  MRtrix sh2peaks: 4D, 3K volumes (x y z per peak), WORLD frame, amplitude = vector length,
//                 NaN triplets where a voxel has fewer peaks.
//   dipy-peaks    DIPY reshape_peaks_for_visualization: 4D, 3K volumes, VOXEL frame (rotated by the
//                 affine's rotation), zeros where absent; amplitude = vector length (1 for unit peaks).
//   bedpostx      FSL bedpostx folder: dyadsN.nii[.gz] (3 volumes, unit) with mean_fNsamples.nii[.gz] as
//                 amplitudes; FSL frame: voxel axes, x negated when det(affine) > 0.
//   dsi-studio    DSI Studio .fib[.gz] (io/formats/dsi_studio.h): the first three populations, fa0..fa2 (quantitative
//                 anisotropy) as amplitudes; its dti_fa is the paired FA. Detected by format, never written.
//   dtifit-v1     FSL dtifit set with V1 but none of L1-L3: V1 as one population, amplitude 1, the set's FA
//   as
//                 the paired FA; FSL frame as bedpostx. Detected by the member names, never written.
// Detection (Auto) says why in layoutReason: a dtfabric descrip marker, a bedpostx name, else the frame of
// a peaks file by fibre coherence (io/model/fibre_set.h: the frame in which first peaks continue along
// themselves; on a grid whose rotation is the identity both frames are the same). All functions throw
// InputError whose message starts with the file name (UsageError for a bad layout name).
#pragma once

#include "io/model/fibre_set.h"
#include "io/formats/tensor_io.h"

#include <string>
#include <vector>

namespace dtf::io {

enum class FibreLayout { Auto, MrtrixPeaks, DipyPeaks, Bedpostx, DsiStudio, DtifitV1 };

const char* fibreLayoutName(FibreLayout l);
// True for mrtrix-peaks, dipy-peaks, bedpostx and fibres-auto (the names --layout takes for fibre sets).
bool isFibreLayoutName(const std::string& name);
// Parses mrtrix-peaks|dipy-peaks|bedpostx|auto; throws UsageError otherwise.
FibreLayout parseFibreLayout(const std::string& name);

// The rotation from a layout's stored frame to world RAS on grid g: identity for mrtrix-peaks, the grid's
// rotation for dipy-peaks, the FSL frame (the rotation with x negated when det(affine) > 0) for bedpostx.
glm::dmat3 fibreFrameToWorld(const Grid& g, FibreLayout l);

struct LoadedFibres {
  FibreSet set;
  FibreLayout layout = FibreLayout::Auto;
  std::string layoutReason;       // why this layout/frame was chosen (always shown to the user)
  VolumeHeader header;            // of the peaks file or dyads1
  std::vector<std::string> files; // the files read
  std::vector<std::string> warnings;
  ScalarVolume fa; // the file's own FA (dsi-studio dti_fa, dtifit FA) on the set's grid; empty when none
};

// Whether `path` is a fibre file rather than a tensor or DWI: a DSI Studio FIB file, an FSL dtifit set
// (its basename or V1 file) with V1 but no L1-L3, a folder or a dyadsN/mean_fNsamples name (bedpostx), a
// descrip written by writeFibres, or a 4D file with 3K volumes (K >= 2, no sibling .bval) whose values are
// triplets like peaks and (6 volumes) not a positive semi-definite tensor: see detail::componentEvidence
// (io/formats/format_detail.h), which judges what the values can be, not their signs. A single-peak file
// (3 volumes, e.g. a V1 map) is never detected: name its layout. `reason` says why either way. Reads the data
// of 4D files. Throws InputError for unreadable files.
bool looksLikeFibres(const std::string& path, std::string* reason = nullptr);
// The same for a file whose format was detected already (detectFormat; see io/input.h).
bool looksLikeFibres(const std::string& path, const FormatGuess& format, std::string* reason = nullptr);

// Reads a fibre file (see the layouts above; dsi-studio and dtifit-v1 only by Auto). Throws InputError for
// unreadable files, a volume count that is not a multiple of 3, Inf or partly-NaN triplets, no fibre at all,
// or (bedpostx) a missing fractions file or dyads/fractions on different grids.
LoadedFibres readFibres(const std::string& path, FibreLayout layout = FibreLayout::Auto);
LoadedFibres readFibres(const std::string& path, const FormatGuess& format, FibreLayout layout);

// Writes `set` in `layout` (not Auto): a peaks file at `path` (.nii or .nii.gz), or for bedpostx a folder
// `path` with dyadsN.nii.gz and mean_fNsamples.nii.gz (N = 1..K). Amplitudes are written as vector lengths
// (peaks) or fractions. Each file is written atomically. Throws InputError/UsageError.
void writeFibres(const std::string& path, const FibreSet& set, FibreLayout layout, int niftiVersion = 1);

} // namespace dtf::io
