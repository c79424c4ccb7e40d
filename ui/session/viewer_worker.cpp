// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/viewer_worker.h"

#include "io/model/error.h"
#include "ui/session/fibre_input.h"
#include "ui/session/tensor_input.h"

#include <chrono>
#include <sstream>

namespace dtf::session {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

Mesh extractViewerSurface(const ViewerDataset& data, const SurfaceSpec& spec) {
  if (data.fibres) {
    FibreInput needs; // what checkFibreSurface looks at: a paired tensor and FA
    if (data.pairedTensor) needs.tensor.emplace();
    if (!data.fa.data.empty()) needs.fa.data.resize(1);
    checkFibreSurface(spec, needs);
  }
  if (spec.kind == SurfaceSpec::Kind::Fa && data.sweeper) {
    Mesh m = data.sweeper->extract(spec.value);
    if (m.empty()) {
      std::ostringstream o;
      o << "FA threshold " << spec.value << " yields no surface";
      throw InputError(o.str());
    }
    return m;
  }
  return buildSurface(spec, data.loaded.field, data.fa, data.buildOptions);
}

ViewerWorker::ViewerWorker()
    : worker_(
          [](Job& job, WorkContext& context) -> std::optional<WorkerResult> {
            const auto t0 = std::chrono::steady_clock::now();
            WorkerResult r = std::holds_alternative<LoadJob>(job) ? load(std::get<LoadJob>(job), context)
                                                                  : surface(std::get<SurfaceJob>(job));
            r.ms = msSince(t0);
            return r;
          },
          {WorkLane{}, WorkLane{}}) {}

ViewerWorker::~ViewerWorker() = default;

void ViewerWorker::requestLoad(std::uint64_t id, const std::string& path, const std::string& layout,
                               const std::string& tensorPath, const SurfaceSpec& first, bool sliceWithoutFa) {
  worker_.request(LoadJob{id, path, layout, tensorPath, first, sliceWithoutFa}, kLoad,
                  {kSurface}); // waiting surfaces belong to old data
}

void ViewerWorker::requestSurface(std::uint64_t id, std::shared_ptr<const ViewerDataset> data,
                                  const SurfaceSpec& spec) {
  worker_.request(SurfaceJob{id, std::move(data), spec}, kSurface);
}

bool ViewerWorker::poll(WorkerResult& out) {
  return worker_.poll(out);
}

bool ViewerWorker::busy() const {
  return worker_.busy();
}

bool ViewerWorker::loading(std::string* stage) const {
  worker_.progress(kLoad, stage);
  return worker_.pending(kLoad);
}

WorkerResult ViewerWorker::load(const LoadJob& job, WorkContext& context) {
  WorkerResult r;
  r.id = job.id;
  try {
    context.setStage("reading " + job.path);
    auto data = std::make_shared<ViewerDataset>();
    data->path = job.path;
    SurfaceSpec first = job.first;
    try {
      TensorInputOptions options;
      options.quiet = true;
      options.onStage = [&context](const std::string& stage) { context.setStage(stage); };
      const io::OpenedInput opened = io::openInput(inputRequest(job.path, job.layout, options, true));
      if (opened.kind == io::InputKind::Fibres) {
        FibreInput in = loadFibreInput(opened, job.tensorPath, true);
        data->pairedTensor = in.tensor.has_value();
        data->loaded.layoutReason = in.fibres.layoutReason;
        data->loaded.header = in.fibres.header;
        data->loaded.warnings = in.fibres.warnings;
        if (in.tensor) data->loaded.layout = in.tensor->layout;
        data->loaded.field = std::move(in.carrier);
        data->fa = std::move(in.fa);
        data->faSource = in.faSource;
        data->fibres = std::make_shared<const io::LoadedFibres>(std::move(in.fibres));
        if (job.sliceWithoutFa && data->fa.data.empty() && first.kind == SurfaceSpec::Kind::Fa)
          first = parseSurfaceSpec("slice=axial");
      } else {
        if (!job.tensorPath.empty())
          throw UsageError("a paired tensor (" + job.tensorPath + ") goes with a fibre set; " + job.path +
                           " is not one");
        options.layout = io::parseLayout(job.layout);
        data->loaded = loadTensors(opened, options);
        context.setStage("computing FA");
        data->fa = computeFaMap(data->loaded.field);
      }
    } catch (...) {
      rethrowWithContext("while loading " + job.path);
    }
    if (!data->fa.data.empty()) {
      context.setStage("preparing the FA isosurface sweeper");
      surfaces::IsosurfaceOptions io;
      io.smoothSigmaVoxels = data->buildOptions.smoothSigmaVoxels;
      io.minComponentFraction = data->buildOptions.minComponentFraction;
      io.meshSmoothIterations = data->buildOptions.meshSmoothIterations;
      io.maxShiftVoxels = data->buildOptions.maxShiftVoxels;
      data->sweeper = std::make_unique<surfaces::IsosurfaceSweeper>(data->fa, io);
    }
    const Grid& g = data->loaded.field.grid;
    g.worldBounds(data->lo, data->hi);
    const glm::dvec3 half = 0.5 * g.spacing;
    data->lo -= half;
    data->hi += half;
    context.setStage("extracting the surface");
    r.kind = WorkerResult::Kind::Loaded;
    r.spec = first;
    try {
      r.mesh = extractViewerSurface(*data, first);
    } catch (...) {
      r.error = "while building the " + describeSurface(first) + ": " + currentExceptionMessage();
    }
    r.data = std::move(data);
  } catch (...) {
    r.kind = WorkerResult::Kind::Failed;
    r.error = currentExceptionMessage();
  }
  return r;
}

WorkerResult ViewerWorker::surface(const SurfaceJob& job) {
  WorkerResult r;
  r.id = job.id;
  r.spec = job.spec;
  try {
    // An empty FA isosurface is a normal result while sweeping, not an error.
    const ViewerDataset& d = *job.data;
    r.mesh = job.spec.kind == SurfaceSpec::Kind::Fa && d.sweeper ? d.sweeper->extract(job.spec.value)
                                                                 : extractViewerSurface(d, job.spec);
    r.kind = WorkerResult::Kind::Surface;
  } catch (...) {
    r.kind = WorkerResult::Kind::Failed;
    r.error = currentExceptionMessage();
  }
  return r;
}

} // namespace dtf::session
