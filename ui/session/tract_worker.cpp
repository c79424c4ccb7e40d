// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_worker.h"

#include "io/model/error.h"
#include "surfaces/mesh_checks.h"
#include "surfaces/analyses/near_surface.h"
#include "surfaces/selection/tract_selection.h"
#include "surfaces/slices.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_overlay.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace dtf::session {

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

TractResult failed(std::uint64_t id, const char* what, const std::string& error) {
  TractResult r;
  r.kind = TractResult::Kind::Failed;
  r.id = id;
  r.what = what;
  r.error = error;
  return r;
}

} // namespace

TractWorker::TractWorker()
    : analysis_([this](AnalysisJob& job, WorkContext& context) { return analyse(job, context); },
                {WorkLane{true, true}, WorkLane{false, false}, WorkLane{true, false}}),
      tracker_([](TrackingJob& job, WorkContext& context) -> std::optional<TractResult> {
        const auto t0 = std::chrono::steady_clock::now();
        TractResult r;
        try {
          r = track(job, context);
        } catch (...) {
          r = failed(job.id, "tracking", currentExceptionMessage());
        }
        r.ms = msSince(t0);
        return r;
      }) {}

TractWorker::~TractWorker() = default;

void TractWorker::requestSelection(SelectionJob job) {
  analysis_.request(std::move(job), kSelection); // cancels a running selection: it is out of date
}

void TractWorker::requestAgreement(AgreementJob job) {
  analysis_.request(std::move(job), kAgreement);
}

void TractWorker::requestSave(SaveJob job) {
  analysis_.request(std::move(job), kSave);
}

void TractWorker::requestTracking(TrackingJob job) {
  if (tracker_.pending(0)) throw UsageError("tracking is already running");
  lastFraction_ = 0;
  tracker_.request(std::move(job));
}

void TractWorker::cancelTracking() {
  tracker_.cancel(0);
}

bool TractWorker::poll(TractResult& out) {
  return analysis_.poll(out) || tracker_.poll(out);
}

bool TractWorker::busy() const {
  return analysis_.busy() || tracker_.busy();
}

bool TractWorker::tracking(std::size_t* seedsDone, double* fraction) const {
  std::size_t done = 0, planned = 0;
  tracker_.progress(0, nullptr, &done, &planned);
  if (seedsDone) *seedsDone = done;
  if (fraction) {
    const double f = planned ? static_cast<double>(done) / static_cast<double>(planned) : 0.0;
    // trackSelect plans batch by batch: keep the bar from running backwards.
    lastFraction_ = std::max(lastFraction_, std::min(f, 1.0));
    *fraction = lastFraction_;
  }
  return tracker_.pending(0);
}

bool TractWorker::agreementRunning() const {
  return analysis_.pending(kAgreement);
}

TractResult TractWorker::select(const SelectionJob& job, const WorkContext& context) {
  TractResult r;
  r.kind = TractResult::Kind::Selection;
  r.id = job.id;
  r.pointCap = job.pointCap;
  if (job.choice) {
    if (job.choice != choice_) {
      choice_.reset();
      chosen_ = prepareShownTracts(*job.choice);
      choice_ = job.choice;
    }
    r.shown = chosen_.lines;
    r.applied = chosen_.applied;
  }
  const Polylines& all = job.choice ? *r.shown : *job.tracts;
  TractSelection s =
      job.mesh ? selectTracts(all, *job.mesh, job.nearMm, &context.cancelFlag(), job.pointCap) : TractSelection{};
  if (context.cancelled()) return failed(job.id, "selection", "cancelled");
  if (!all_ || allSerial_ != job.tractsSerial) {
    all_ = std::make_shared<const render::DisplayTracts>(tractOverlayDisplay(all));
    allSerial_ = job.tractsSerial;
  }
  r.allDisplay = all_;
  if (s.all) {
    r.display = all_;
    r.lines = all.lineCount();
    r.points = all.points.size();
    r.slab = s.pick.plane.has_value();
    if (s.pick.plane) r.plane = *s.pick.plane;
  } else {
    r.display = std::make_shared<const render::DisplayTracts>(tractOverlayDisplay(s.near));
    r.lines = s.near.lineCount();
    r.points = s.near.points.size();
    r.lineStep = s.lineStep;
  }
  return r;
}

std::optional<TractResult> TractWorker::analyse(AnalysisJob& job, WorkContext& context) {
  const auto t0 = std::chrono::steady_clock::now();
  TractResult r;
  if (auto* selection = std::get_if<SelectionJob>(&job)) {
    try {
      r = select(*selection, context);
    } catch (...) {
      r = failed(selection->id, "selecting the tracts near the surface", currentExceptionMessage());
    }
    // A cancelled selection was replaced by a newer request: nothing to report.
    if (context.cancelled()) return std::nullopt;
  } else if (auto* save = std::get_if<SaveJob>(&job)) {
    try {
      if (!save->overwrite && std::filesystem::exists(save->path))
        throw InputError(save->path + " exists: refusing to overwrite it");
      const Grid* reference = save->reference ? &*save->reference : nullptr;
      if (!save->keep) {
        writeTracts(save->path, *save->tracts, reference);
      } else if (save->asGroup.empty()) {
        writeTracts(save->path, surfaces::subsetWithGroups(*save->tracts, *save->keep), reference);
      } else {
        Polylines all = *save->tracts; // the group is added to a copy: the tracts on screen stay as loaded
        if (std::any_of(all.groups.begin(), all.groups.end(),
                        [&](const TractGroup& g) { return g.name == save->asGroup; }))
          throw InputError("the tracts already hold a group '" + save->asGroup + "' (choose another name)");
        all.groups.push_back({save->asGroup, *save->keep});
        writeTracts(save->path, all, reference);
      }
      r.kind = TractResult::Kind::Saved;
      r.id = save->id;
      r.path = save->path;
    } catch (...) {
      r = failed(save->id, "saving the tracts", currentExceptionMessage());
    }
  } else {
    auto& agreement = std::get<AgreementJob>(job);
    try {
      r.kind = TractResult::Kind::Agreement;
      r.id = agreement.id;
      r.agreement = surfaces::tractSurfaceAgreement(*agreement.tracts, *agreement.mesh,
                                                    agreement.data->loaded.field, agreement.options);
    } catch (...) {
      r = failed(agreement.id, "computing the agreement with the fabric", currentExceptionMessage());
    }
  }
  r.ms = msSince(t0);
  return r;
}

TractResult TractWorker::track(const TrackingJob& job, WorkContext& context) {
  const ViewerDataset& data = *job.data;
  const surfaces::SeedSource source =
      seedsFor(job.request, data.loaded.field, &data.fa, job.mesh.get(), nullptr);
  surfaces::TrackingOptions o = job.request.options;
  o.cancel = &context.cancelFlag();
  o.progress = [&context](std::size_t done, std::size_t planned) { context.setCount(done, planned); };
  const TrackRequest& q = job.request;
  surfaces::TrackingResult t;
  if (q.count == SeedCount::Select) {
    if (q.number < 1) throw UsageError("the number of streamlines must be positive");
    t = surfaces::trackSelect(data.loaded.field, source, static_cast<std::size_t>(q.number), o);
  } else if (q.count == SeedCount::Seeds) {
    if (q.number < 1) throw UsageError("the number of seeds must be positive");
    t = surfaces::trackSeeds(data.loaded.field, source, static_cast<std::uint64_t>(q.number), o);
  } else {
    if (q.number < 1) throw UsageError("seeds per voxel must be positive");
    t = surfaces::trackSeeds(data.loaded.field, source, source.count, o);
  }
  TractResult r;
  r.kind = TractResult::Kind::Tracking;
  r.id = job.id;
  r.cancelled = t.cancelled;
  char text[320];
  if (t.cancelled) {
    std::snprintf(text, sizeof text, "tracking cancelled after %zu seeds (%zu streamlines discarded)",
                  t.seedsTried, t.lines.lineCount());
    r.report = text;
    return r;
  }
  if (t.lines.lineCount() == 0) {
    std::snprintf(
        text, sizeof text,
        "no streamline passed from %zu seeds (%zu below FA %g or outside the data, %zu shorter than %g mm)",
        t.seedsTried, t.seedsBelowFa, o.faStop, t.tooShort, o.minLengthMm);
    throw InputError(text);
  }
  std::snprintf(text, sizeof text,
                "tracked %zu streamlines (%zu points) from %zu seeds (%zu below FA, %zu too short)",
                t.lines.lineCount(), t.lines.points.size(), t.seedsTried, t.seedsBelowFa, t.tooShort);
  r.report = std::string(text) + "; seeds: " + source.description;
  r.tracts = std::make_shared<const Polylines>(std::move(t.lines));
  return r;
}

} // namespace dtf::session
