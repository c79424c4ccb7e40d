#include "app/scene/tract_worker.h"

#include "app/scene/tract_files.h"
#include "app/scene/tract_overlay.h"
#include "io/model/error.h"
#include "surfaces/mesh_checks.h"
#include "surfaces/near_surface.h"
#include "surfaces/slices.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace dtf::app {

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

surfaces::SeedSource seedsFor(const ui::TrackRequest& r, const ViewerDataset& data, const Mesh* surface) {
  const TensorField& field = data.loaded.field;
  const auto seed = static_cast<std::uint64_t>(std::max(r.rngSeed, 0));
  if (r.count == ui::SeedCount::PerVoxel && r.seeds != ui::SeedKind::FaMask)
    throw UsageError("seeds per voxel need FA-mask seeds");
  switch (r.seeds) {
  case ui::SeedKind::Surface:
    if (!surface || surface->empty()) throw UsageError("no surface on screen to seed from");
    return surfaces::seedsOnSurface(*surface, seed);
  case ui::SeedKind::Slice: {
    if (r.sliceAxis < 0 || r.sliceAxis > 2) throw UsageError("seed slice axis must be 0, 1 or 2");
    const auto axis = static_cast<surfaces::SliceAxis>(r.sliceAxis);
    return surfaces::seedsOnSlice(field, surfaces::voxelAxisFor(field.grid, axis), r.sliceIndex, nullptr,
                                  seed);
  }
  case ui::SeedKind::Sphere:
    return surfaces::seedsInSphere(r.centre, r.radiusMm, seed);
  case ui::SeedKind::FaMask: {
    if (!(r.faMask > 0 && r.faMask < 1)) throw UsageError("the seed FA threshold must lie in (0, 1)");
    MaskVolume mask(data.fa.grid, 1);
    for (std::size_t i = 0; i < data.fa.grid.voxelCount(); ++i)
      mask.data[i] = data.fa.data[i * static_cast<std::size_t>(data.fa.components)] >= r.faMask ? 1 : 0;
    char what[64];
    std::snprintf(what, sizeof what, " (FA >= %g)", r.faMask);
    surfaces::SeedSource s =
        surfaces::seedsFromMask(mask, r.count == ui::SeedCount::PerVoxel ? r.number : 0, seed);
    s.description += what;
    return s;
  }
  }
  throw UsageError("unknown seed kind");
}

TractWorker::TractWorker() : analysis_([this] { runAnalysis(); }), tracker_([this] { runTracking(); }) {}

TractWorker::~TractWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  cancelSelection_ = true;
  cancelTracking_ = true;
  wake_.notify_all();
  analysis_.join();
  tracker_.join();
}

void TractWorker::requestSelection(SelectionJob job) {
  {
    std::lock_guard lock(mutex_);
    selection_ = std::move(job);
    if (analysisRunning_) cancelSelection_ = true; // the running one (if a selection) is out of date
  }
  wake_.notify_all();
}

void TractWorker::requestAgreement(AgreementJob job) {
  {
    std::lock_guard lock(mutex_);
    agreement_ = std::move(job);
  }
  wake_.notify_all();
}

void TractWorker::requestSave(SaveJob job) {
  {
    std::lock_guard lock(mutex_);
    saves_.push_back(std::move(job));
  }
  wake_.notify_all();
}

void TractWorker::requestTracking(TrackingJob job) {
  {
    std::lock_guard lock(mutex_);
    if (tracking_ || trackingRunning_) throw UsageError("tracking is already running");
    tracking_ = std::move(job);
    cancelTracking_ = false;
    seedsDone_ = 0;
    seedsPlanned_ = 0;
    lastFraction_ = 0;
  }
  wake_.notify_all();
}

void TractWorker::cancelTracking() {
  cancelTracking_ = true;
}

bool TractWorker::poll(TractResult& out) {
  std::lock_guard lock(mutex_);
  if (results_.empty()) return false;
  out = std::move(results_.front());
  results_.pop_front();
  return true;
}

bool TractWorker::busy() const {
  std::lock_guard lock(mutex_);
  return analysisRunning_ || trackingRunning_ || selection_ || agreement_ || tracking_ || !saves_.empty() ||
         !results_.empty();
}

bool TractWorker::tracking(std::size_t* seedsDone, double* fraction) const {
  std::lock_guard lock(mutex_);
  if (seedsDone) *seedsDone = seedsDone_;
  if (fraction) {
    const std::size_t planned = seedsPlanned_;
    const double f = planned ? static_cast<double>(seedsDone_) / static_cast<double>(planned) : 0.0;
    // trackSelect plans batch by batch: keep the bar from running backwards.
    lastFraction_ = std::max(lastFraction_, std::min(f, 1.0));
    *fraction = lastFraction_;
  }
  return trackingRunning_ || tracking_;
}

bool TractWorker::agreementRunning() const {
  std::lock_guard lock(mutex_);
  return agreementRunning_ || agreement_;
}

void TractWorker::push(TractResult&& r) {
  std::lock_guard lock(mutex_);
  results_.push_back(std::move(r));
}

TractResult TractWorker::select(const SelectionJob& job) {
  TractResult r;
  r.kind = TractResult::Kind::Selection;
  r.id = job.id;
  const Polylines& all = *job.tracts;
  auto everything = [&] {
    if (!all_ || allSerial_ != job.tractsSerial) {
      all_ = std::make_shared<const render::DisplayTracts>(render::prepareDisplayTracts(all));
      allSerial_ = job.tractsSerial;
    }
    r.display = all_;
    r.lines = all.lineCount();
    r.points = all.points.size();
  };
  const TractPick pick = job.mesh ? pickTracts(*job.mesh, job.nearMm) : TractPick{};
  if (!pick.nearOnly) {
    everything();
    r.slab = pick.plane.has_value();
    if (pick.plane) r.plane = *pick.plane;
  } else {
    surfaces::NearSurfaceOptions o;
    o.cancel = &cancelSelection_;
    const surfaces::DistanceQuery query(*job.mesh);
    const Polylines near = surfaces::selectNearSurface(all, query, job.nearMm, o);
    if (cancelSelection_) return failed(job.id, "selection", "cancelled");
    r.display = std::make_shared<const render::DisplayTracts>(render::prepareDisplayTracts(near));
    r.lines = near.lineCount();
    r.points = near.points.size();
  }
  return r;
}

void TractWorker::runAnalysis() {
  while (true) {
    std::optional<SelectionJob> selection;
    std::optional<AgreementJob> agreement;
    std::optional<SaveJob> save;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || selection_ || agreement_ || !saves_.empty(); });
      if (stop_) return;
      if (selection_) {
        selection.swap(selection_);
        cancelSelection_ = false;
      } else if (!saves_.empty()) {
        save = std::move(saves_.front());
        saves_.pop_front();
      } else {
        agreement.swap(agreement_);
        agreementRunning_ = true;
      }
      analysisRunning_ = true;
    }
    const auto t0 = std::chrono::steady_clock::now();
    TractResult r;
    if (selection) {
      try {
        r = select(*selection);
      } catch (...) {
        r = failed(selection->id, "selecting the tracts near the surface", currentExceptionMessage());
      }
    } else if (save) {
      try {
        if (!save->overwrite && std::filesystem::exists(save->path))
          throw InputError(save->path + " exists: refusing to overwrite it");
        writeTracts(save->path, *save->tracts, save->reference ? &*save->reference : nullptr);
        r.kind = TractResult::Kind::Saved;
        r.id = save->id;
        r.path = save->path;
      } catch (...) {
        r = failed(save->id, "saving the tracts", currentExceptionMessage());
      }
    } else {
      try {
        r.kind = TractResult::Kind::Agreement;
        r.id = agreement->id;
        r.agreement = surfaces::tractSurfaceAgreement(*agreement->tracts, *agreement->mesh,
                                                      agreement->data->loaded.field, agreement->options);
      } catch (...) {
        r = failed(agreement->id, "computing the agreement with the fabric", currentExceptionMessage());
      }
    }
    r.ms = msSince(t0);
    std::lock_guard lock(mutex_);
    // A cancelled selection was replaced by a newer request: nothing to report.
    if (!(r.kind == TractResult::Kind::Failed && r.error == "cancelled" && selection))
      results_.push_back(std::move(r));
    analysisRunning_ = false;
    agreementRunning_ = false;
  }
}

TractResult TractWorker::track(const TrackingJob& job) {
  const ViewerDataset& data = *job.data;
  const surfaces::SeedSource source = seedsFor(job.request, data, job.mesh.get());
  surfaces::TrackingOptions o = trackingOptions(job.request);
  o.cancel = &cancelTracking_;
  o.progress = [this](std::size_t done, std::size_t planned) {
    std::lock_guard lock(mutex_);
    seedsDone_ = done;
    seedsPlanned_ = planned;
  };
  const ui::TrackRequest& q = job.request;
  surfaces::TrackingResult t;
  if (q.count == ui::SeedCount::Select) {
    if (q.number < 1) throw UsageError("the number of streamlines must be positive");
    t = surfaces::trackSelect(data.loaded.field, source, static_cast<std::size_t>(q.number), o);
  } else if (q.count == ui::SeedCount::Seeds) {
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

void TractWorker::runTracking() {
  while (true) {
    std::optional<TrackingJob> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || tracking_; });
      if (stop_) return;
      job.swap(tracking_);
      trackingRunning_ = true;
    }
    const auto t0 = std::chrono::steady_clock::now();
    TractResult r;
    try {
      r = track(*job);
    } catch (...) {
      r = failed(job->id, "tracking", currentExceptionMessage());
    }
    r.ms = msSince(t0);
    std::lock_guard lock(mutex_);
    results_.push_back(std::move(r));
    trackingRunning_ = false;
  }
}

} // namespace dtf::app
