// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's Profile panel, its computation: the profile of the streamlines the viewer profiles (the
// selection's, or all on screen) along one scalar of the data on screen, by the engine `dtfabric profile`
// runs (surfaces/analyses/tract_profile.h: the same orientation, resampling, gauss weights and seeded
// bootstrap with the same defaults, the scalar maps computed as ui/session/tract_profiles.h computes them).
// Runs on a worker thread (app/viewer/viewer.h); pure computation on shared, immutable inputs.
#pragma once

#include "io/model/geometry.h"
#include "surfaces/analyses/tract_profile.h"
#include "ui/session/viewer_worker.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dtf::session {

// The scalars the panel offers: the tensor's fa, md, ad and rd (a fibre set with FA: fa).
std::vector<std::string> viewerProfileScalars(const ViewerDataset& data);

struct ViewerProfileJob {
  std::shared_ptr<const Polylines> lines;
  std::shared_ptr<const std::vector<std::uint32_t>> which; // null: every streamline of `lines`
  std::shared_ptr<const ViewerDataset> data;
  std::string scalar = "fa";
  std::uint64_t serial = 0;
};

struct ViewerProfileResult {
  std::uint64_t serial = 0;
  std::string scalar;
  std::string error; // set: no profile
  std::string axis;  // where the core starts and ends, e.g. "inferior → superior"
  surfaces::BundleProfile profile;
};

// Profiles the job's streamlines along its scalar with `dtfabric profile`'s defaults (100 nodes, gauss
// weights, 1000 bootstrap draws, seed 1). Errors (no streamline, no such scalar) go to `error`.
ViewerProfileResult profileForViewer(const ViewerProfileJob& job);

} // namespace dtf::session
