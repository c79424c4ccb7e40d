// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/roi_worker.h"

#include "io/model/error.h"
#include "render/tract_renderer.h"
#include "surfaces/selection/tract_selection.h"
#include "ui/session/tract_overlay.h"

#include <chrono>

namespace dtf::session {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

RoiWorker::RoiWorker()
    : worker_([this](RoiJob& job, WorkContext& context) { return work(job, context); },
              {WorkLane{true, false}}) {}

RoiWorker::~RoiWorker() = default;

void RoiWorker::request(RoiJob job) { worker_.request(std::move(job)); }

bool RoiWorker::poll(RoiResult& out) { return worker_.poll(out); }

RoiResult RoiWorker::run(const RoiJob& job, const surfaces::TractIndex* index) {
  RoiResult r;
  r.id = job.id;
  r.active = job.set.hasRegions() || job.set.hasLengthRange();
  if (!r.active || !job.tracts) return r;
  const auto t0 = std::chrono::steady_clock::now();
  const surfaces::RegionTester tester(job.set); // validates (InputError)
  const surfaces::TractView view = surfaces::viewOf(*job.tracts);
  r.lines = std::make_shared<const std::vector<std::uint32_t>>(surfaces::selectLines(view, tester, index));
  r.selectMs = msSince(t0);
  if (job.subset) // only what is drawn: the full subset of a large selection would be sampled anyway
    r.subset = std::make_shared<const Polylines>(
        job.subsetWholeLines
            ? render::decimateForDisplay(*job.tracts, *r.lines, kNearSurfacePointCap, render::kWholeDisplayLines)
            : render::decimateForDisplay(*job.tracts, *r.lines));
  return r;
}

std::optional<RoiResult> RoiWorker::work(RoiJob& job, WorkContext& context) {
  try {
    double indexMs = 0;
    if (job.tracts && (job.tractsSerial != indexSerial_ || indexed_ != job.tracts)) {
      index_.reset(); // the old index goes before the new one is built (memory)
      indexed_.reset();
      context.setStage("indexing streamlines");
      const auto t0 = std::chrono::steady_clock::now();
      index_ = std::make_unique<surfaces::TractIndex>(surfaces::viewOf(*job.tracts));
      indexed_ = job.tracts;
      indexSerial_ = job.tractsSerial;
      indexMs = msSince(t0);
    }
    context.setStage("selecting");
    RoiResult r = run(job, job.tracts ? index_.get() : nullptr);
    r.indexMs = indexMs;
    return r;
  } catch (...) {
    RoiResult r;
    r.id = job.id;
    r.error = currentExceptionMessage();
    return r;
  }
}

} // namespace dtf::session
