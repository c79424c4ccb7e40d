// SPDX-License-Identifier: GPL-3.0-or-later
// Crossing-fibre INPUT for `info` and `render`: a file io::openInput (io/input.h) found to be a fibre set,
// loaded with an optional paired tensor (--tensor: FA for isosurfaces, FA modulation and the grey
// background).
#pragma once

#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "io/diffusion/uncertainty.h"
#include "io/formats/fibre_io.h"

#include <memory>

#include <optional>
#include <string>

namespace dtf::session {

struct FibreInput {
  io::LoadedFibres fibres;
  std::optional<io::LoadedTensors> tensor; // --tensor, on the same grid
  TensorField carrier;  // the tensor when paired, else fibreCarrierField (surface clipping)
  ScalarVolume fa;      // the paired tensor's FA, else the fibre file's own FA (DSI Studio dti_fa, dtifit FA)
  std::string faSource; // where fa comes from ("" when empty)
};

// Whether `path` opens as a fibre set (io::openFibreSet: `layoutText` names a fibre layout, or is auto and
// the file looks like one).
bool isFibreSet(const std::string& path, const std::string& layoutText);

// Loads the fibre set an opened INPUT is and the optional tensor; logs the layout and its reason unless
// quiet. Throws InputError (also for another kind of file, and when the tensor's grid differs).
FibreInput loadFibreInput(const io::OpenedInput& input, const std::string& tensorPath, bool quiet = false);
// The same for a file known to be a fibre set (layout from `layoutText`: auto or a fibre layout).
FibreInput loadFibreInput(const std::string& path, const std::string& layoutText,
                          const std::string& tensorPath, bool quiet = false);

// Refuses (UsageError) surfaces that need FA (fa=) when there is no FA, or tensor directions (fibre=) when no
// tensor is paired.
void checkFibreSurface(const SurfaceSpec& spec, const FibreInput& input);

// The principal eigenvector of every valid tensor as a one-fibre set, amplitude = FA: a tensor shown the
// multi-population way (e1 only).
FibreSet principalFibres(const TensorField& field);

// An uncertainty map as --uncertainty gives it: a cone map (degrees) or a bedpostx samples folder, whose
// populations keep their own cones and mean directions.
struct UncertaintyMap {
  ScalarVolume cone;                                    // io::readConeMap: population 1 for bedpostx
  std::shared_ptr<const io::BedpostxSamples> samples; // bedpostx only
};
// Reads `path` (io::readConeMap's inputs). Throws InputError naming the file.
UncertaintyMap readUncertainty(const std::string& path);
// The cone map to show: over a fibre set on the samples' grid one cone per fibre (fibre index order, as
// render::FabricRenderer::setUncertainty takes it), each fibre taking the cone of the population whose mean
// direction is nearest (largest |cos|; NaN where that population has no cone), so every population frays by its own
// cone whatever order the set holds them in; otherwise `map.cone`.
ScalarVolume conesFor(const UncertaintyMap& map, const FibreSet* fibres);

} // namespace dtf::session
