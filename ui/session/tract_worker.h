// SPDX-License-Identifier: GPL-3.0-or-later
// The session's tract work off the GUI thread (long work never blocks the window), on two CoalescingWorkers
// (ui/session/coalescing_worker.h): the selection of what is drawn for the surface on screen (the
// tract-overlay rule of ui/session/tract_overlay.h) and its display preparation, the agreement measure and
// saving on one; tracking, which may run for minutes, on the other, with progress and cancel. Selection and
// agreement requests coalesce: a newer request replaces one not started and a newer selection cancels a
// running one, so an FA sweep costs one selection per surface the user can see; saves queue. Results are
// polled by the GUI thread.
#pragma once

#include "io/model/geometry.h"
#include "render/tract_renderer.h"
#include "surfaces/analyses/agreement.h"
#include "surfaces/tracking/tracking.h"
#include "ui/session/actions.h"
#include "ui/session/track_request.h"
#include "ui/session/tract_colouring.h"
#include "ui/session/tract_overlay.h"
#include "ui/session/viewer_worker.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>
#include <variant>

namespace dtf::session {

struct TractResult {
  enum class Kind { Selection, Tracking, Agreement, Saved, Failed } kind = Kind::Failed;
  std::uint64_t id = 0;
  std::string what; // Failed: the job, e.g. "tracking"
  // Selection: what to draw for the surface (shared while the tracts and the choice stay the same).
  std::shared_ptr<const render::DisplayTracts> display;
  // Selection: the display of every tract (the ortho layout's slice panes draw it in a slab around their
  // planes), shared while the tracts and the choice stay the same.
  std::shared_ptr<const render::DisplayTracts> allDisplay;
  bool slab = false;                 // planar surface: every tract, clipped to a slab around `plane`
                                     // (ui/session/tract_overlay.h)
  glm::vec4 plane{0, 0, 1, 0};       // unit normal, offset (world mm)
  std::size_t lines = 0, points = 0; // selected, before display decimation
  std::size_t lineStep = 1;          // near a curved surface: of every lineStep-th streamline (pointCap)
  std::size_t pointCap = 0;          // the job's
  std::shared_ptr<const Polylines> shown; // the job's choice made (SelectionJob::choice)
  TractColouringApplied applied;          // ... and what its colouring applied
  // Tracking: the streamlines and a one-line report; cancelled runs keep nothing.
  std::shared_ptr<const Polylines> tracts;
  std::string report;
  bool cancelled = false;
  surfaces::AgreementResult agreement;
  std::string path; // Saved
  std::string error;
  double ms = 0;
};

struct SelectionJob {
  std::uint64_t id = 0;
  std::shared_ptr<const Polylines> tracts;
  std::uint64_t tractsSerial = 0; // tells the worker when its cached display of all tracts is stale
  std::shared_ptr<const Mesh> mesh;
  double nearMm = 3.0; // curved surfaces: 0 = every tract
  std::size_t pointCap = kNearSurfacePointCap; // points the near-surface rule measures at most
  // Set: `tracts` are made from this choice first (prepareShownTracts) and returned in TractResult::shown.
  std::shared_ptr<const TractChoice> choice;
};

struct TrackingJob {
  std::uint64_t id = 0;
  std::shared_ptr<const ViewerDataset> data;
  std::shared_ptr<const Mesh> mesh; // SeedKind::Surface
  TrackRequest request;             // sliceIndex already resolved (>= 0)
};

struct AgreementJob {
  std::uint64_t id = 0;
  std::shared_ptr<const Polylines> tracts;
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<const ViewerDataset> data;
  surfaces::AgreementOptions options;
};

struct SaveJob {
  std::uint64_t id = 0;
  std::shared_ptr<const Polylines> tracts;
  std::string path;
  std::optional<Grid> reference; // .trk
  bool overwrite = false;
  // Set: only these streamlines of `tracts` (ascending) with every value and group, or with `asGroup` (a
  // .trx output) every streamline with them added as that group.
  std::shared_ptr<const std::vector<std::uint32_t>> keep;
  std::string asGroup;
};

class TractWorker {
public:
  TractWorker();
  // Cancels tracking and a running selection, finishes the running jobs and joins.
  ~TractWorker();
  TractWorker(const TractWorker&) = delete;
  TractWorker& operator=(const TractWorker&) = delete;

  void requestSelection(SelectionJob job);
  void requestAgreement(AgreementJob job);
  void requestSave(SaveJob job);
  // Throws UsageError when tracking is already running.
  void requestTracking(TrackingJob job);
  void cancelTracking();
  // Takes the oldest finished result, if any.
  bool poll(TractResult& out);
  // A job is queued or running, or a result waits to be polled.
  bool busy() const;
  // Tracking is queued or running: seeds done and the fraction done (0..1).
  bool tracking(std::size_t* seedsDone = nullptr, double* fraction = nullptr) const;
  bool agreementRunning() const;

private:
  using AnalysisJob = std::variant<SelectionJob, SaveJob, AgreementJob>;
  enum Lane : std::size_t { kSelection = 0, kSave = 1, kAgreement = 2 };
  std::optional<TractResult> analyse(AnalysisJob& job, WorkContext& context);
  TractResult select(const SelectionJob& job, const WorkContext& context);
  static TractResult track(const TrackingJob& job, WorkContext& context);

  mutable double lastFraction_ = 0; // progress never runs backwards (GUI thread only)
  // The display of every tract, kept while the tract set stays the same (planar surfaces, nearMm 0); used on
  // the analysis thread only.
  std::uint64_t allSerial_ = 0;
  std::shared_ptr<const render::DisplayTracts> all_;
  // The last choice made and its tracts: the jobs that follow carry the same choice until its result is
  // taken (analysis thread only).
  std::shared_ptr<const TractChoice> choice_;
  ShownTracts chosen_;
  // Last: joined before the members their jobs use go.
  CoalescingWorker<AnalysisJob, TractResult> analysis_;
  CoalescingWorker<TrackingJob, TractResult> tracker_;
};

} // namespace dtf::session
