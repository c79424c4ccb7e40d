// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's ROI selection off the UI thread (ui/session/roi_selection.h says what the session publishes):
// one CoalescingWorker (ui/session/coalescing_worker.h) whose jobs carry the tract set and the region set to
// apply. The streamlines' TractIndex (surfaces/selection/tract_selection.h) is built on the worker thread
// the first time a job brings a new tract set (reported as the stage "indexing streamlines") and kept for
// the jobs after it; each job then runs surfaces::selectLines with it, the same call `dtfabric select`
// makes. A request replaces the job still waiting, so dragging a region costs one selection per result the
// user can see; a running selection is not interrupted (its answer is dropped by the session when a newer
// one is on its way).
#pragma once

#include "io/model/geometry.h"
#include "surfaces/selection/regions.h"
#include "ui/session/coalescing_worker.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dtf::surfaces {
class TractIndex;
}

namespace dtf::session {

struct RoiJob {
  std::uint64_t id = 0;
  std::shared_ptr<const Polylines> tracts;
  std::uint64_t tractsSerial = 0; // a new serial: the index is rebuilt
  surfaces::RegionSet set;        // no region and no length range: every streamline (the index is built)
  bool subset = false; // also make the selected streamlines' display subset (what the viewer draws)
  // The subset keeps whole streamlines (every m-th, up to kNearSurfacePointCap points) for a curved surface's
  // near-surface rule, which needs them at full resolution; else the display decimation.
  bool subsetWholeLines = false;
};

struct RoiResult {
  std::uint64_t id = 0;
  bool active = false; // the set had a region or a length range
  std::shared_ptr<const std::vector<std::uint32_t>> lines; // active: the kept streamlines, ascending
  // job.subset and active: render::decimateForDisplay of the kept streamlines (with their values and
  // groups): every point of a selection under render::kTractDisplayPointCap points (subsetWholeLines:
  // kNearSurfacePointCap), else a display sample.
  std::shared_ptr<const Polylines> subset;
  std::string error;   // non-empty: the selection failed (nothing else is set)
  double indexMs = 0;  // time spent building the index in this job (0: reused)
  double selectMs = 0;
};

class RoiWorker {
public:
  RoiWorker();
  ~RoiWorker(); // drops waiting jobs, finishes the running one and joins
  RoiWorker(const RoiWorker&) = delete;
  RoiWorker& operator=(const RoiWorker&) = delete;

  void request(RoiJob job);
  bool poll(RoiResult& out);
  bool busy() const { return worker_.busy(); }
  // The running job's stage ("indexing streamlines", "selecting"); false when none runs. Assigns `stage`
  // only when it differs (no allocation per frame).
  bool progress(std::string* stage) const { return worker_.progress(0, stage); }

  // The selection a job computes, on the calling thread: with `index` when given (built on job.tracts).
  static RoiResult run(const RoiJob& job, const surfaces::TractIndex* index);

private:
  std::optional<RoiResult> work(RoiJob& job, WorkContext& context);

  // Worker thread only: the index of the tract set with serial indexSerial_.
  std::uint64_t indexSerial_ = 0;
  std::shared_ptr<const Polylines> indexed_;
  std::unique_ptr<surfaces::TractIndex> index_;
  // Last: joined before the members its jobs use go.
  CoalescingWorker<RoiJob, RoiResult> worker_;
};

} // namespace dtf::session
