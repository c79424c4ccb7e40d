// One tractography run, as `dtfabric track` and the Python module's dtfabric.track run it: the tensors (a
// file, a DWI or an in-memory field), where to seed, how many, and the tracking options in; the streamlines
// (world RAS mm) and the counts out. Seeding is deterministic: the result depends on the request only.
#pragma once

#include "io/model/tensor_field.h"
#include "surfaces/tracking/tracking.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"

#include <glm/glm.hpp>
#include <optional>
#include <string>

namespace dtf::session {

struct TrackRequest {
  std::string input;                  // tensor file or DWI
  const TensorField* field = nullptr; // when set: these tensors instead of loading `input`
  TensorInputOptions tensorOptions;
  // Seeds: at most one of these; none = random points in the voxels where the input holds a tensor.
  std::string seedsMask;                // random points in the non-zero voxels of this NIfTI mask
  std::optional<glm::dvec4> seedSphere; // centre x, y, z and radius (world mm)
  std::optional<SurfaceSpec> seedSurface;
  std::optional<std::string> seedSliceAxis; // axial | coronal | sagittal, with seedSliceIndex
  int seedSliceIndex = 0;
  // How many: seedsPerVoxel > 0 (with seedsMask), else seedCount > 0 seeds, else select streamlines.
  int select = 1000;
  int seedCount = 0;
  int seedsPerVoxel = 0;
  std::uint64_t rngSeed = 1;
  std::string stopMask;              // stop where this NIfTI mask is zero
  surfaces::TrackingOptions options; // mask is set from stopMask by the job
};

struct TrackRun {
  surfaces::TrackingResult result;
  std::string seedDescription; // e.g. "random points in 12000 voxels of mask.nii.gz"
  std::string mode;            // "select 1000", "500 seeds"
  double seconds = 0;          // tracking time
  Grid grid;                   // the tensors' grid (.trk/.trx headers)
};

// The non-zero voxels of a NIfTI volume as a mask. Throws InputError naming the file.
MaskVolume loadMaskVolume(const std::string& path);

// Validates the options (UsageError), loads the input (unless `field` is given), builds the seeds and
// tracks. Throws InputError naming the file for bad data, UsageError for bad combinations.
TrackRun runTrack(const TrackRequest& request);

} // namespace dtf::session
