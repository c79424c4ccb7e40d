// SPDX-License-Identifier: GPL-3.0-or-later
// One tractography run, as `dtfabric track` and the Python module's dtfabric.track run it: a TrackRequest
// (track_request.h) in; the streamlines (world RAS mm) and the counts out. Seeding is deterministic: the
// result depends on the request only.
#pragma once

#include "ui/session/track_request.h"

#include <string>

namespace dtf::session {

struct TrackRun {
  surfaces::TrackingResult result;
  std::string seedDescription; // e.g. "random points in 12000 voxels of mask.nii.gz"
  std::string mode;            // "select 1000", "500 seeds"
  double seconds = 0;          // tracking time
  Grid grid;                   // the tensors' grid (.trk/.trx headers)
};

// The non-zero voxels of a NIfTI volume as a mask. Throws InputError naming the file.
MaskVolume loadMaskVolume(const std::string& path);

// Validates the request (UsageError), loads the input (unless `field` is given), builds the seeds and
// tracks; Surface seeds need a spec. Throws InputError naming the file for bad data, UsageError for bad combinations.
TrackRun runTrack(const TrackRequest& request);

} // namespace dtf::session
