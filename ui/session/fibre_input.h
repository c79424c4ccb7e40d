// Crossing-fibre INPUT for `info` and `render`: decides whether a file is a fibre set (io/formats/fibre_io.h), loads
// it with an optional paired tensor (--tensor: FA for isosurfaces, FA modulation and the grey background),
// and describes one voxel's fibres for `dtfabric info --voxel`.
#pragma once

#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "io/formats/fibre_io.h"

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

// True when `layoutText` names a fibre layout, or is auto and `path` looks like a fibre file (the reason is
// logged unless quiet).
bool isFibreInput(const std::string& path, const std::string& layoutText, bool quiet = false);

// Loads the fibre set (layout from `layoutText`: auto or a fibre layout) and the optional tensor; logs the
// layout and its reason unless quiet. Throws InputError (also when the tensor's grid differs).
FibreInput loadFibreInput(const std::string& path, const std::string& layoutText,
                          const std::string& tensorPath, bool quiet = false);

// Refuses (UsageError) surfaces that need FA (fa=) when there is no FA, or tensor directions (fibre=) when no
// tensor is paired.
void checkFibreSurface(const SurfaceSpec& spec, const FibreInput& input);

// The principal eigenvector of every valid tensor as a one-fibre set, amplitude = FA: a tensor shown the
// multi-population way (e1 only).
FibreSet principalFibres(const TensorField& field);

// `dtfabric info` for a fibre file: summary, or with ijk the voxel's fibres ("fibres": [{"direction": [x, y,
// z], "amplitude": a}, ...], unit world RAS, strongest first) and, with a paired tensor, its FA and e1.
int describeFibreInput(const std::string& path, const std::string& layoutText, const std::string& tensorPath,
                       const int* ijk, bool json);

} // namespace dtf::session
