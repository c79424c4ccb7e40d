#include "app/scene/viewer_worker.h"

#include "app/scene/tensor_input.h"
#include "io/model/error.h"

#include <chrono>
#include <sstream>

namespace dtf::app {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

Mesh extractViewerSurface(const ViewerDataset& data, const SurfaceSpec& spec) {
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

ViewerWorker::ViewerWorker() : thread_([this] { run(); }) {}

ViewerWorker::~ViewerWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void ViewerWorker::requestLoad(std::uint64_t id, const std::string& path, io::TensorLayout layout,
                               const SurfaceSpec& first) {
  {
    std::lock_guard lock(mutex_);
    load_ = LoadJob{id, path, layout, first};
    surface_.reset(); // belongs to the data being replaced
  }
  wake_.notify_all();
}

void ViewerWorker::requestSurface(std::uint64_t id, std::shared_ptr<const ViewerDataset> data,
                                  const SurfaceSpec& spec) {
  {
    std::lock_guard lock(mutex_);
    surface_ = SurfaceJob{id, std::move(data), spec};
  }
  wake_.notify_all();
}

bool ViewerWorker::poll(WorkerResult& out) {
  std::lock_guard lock(mutex_);
  if (results_.empty()) return false;
  out = std::move(results_.front());
  results_.pop_front();
  return true;
}

bool ViewerWorker::busy() const {
  std::lock_guard lock(mutex_);
  return running_ || load_ || surface_ || !results_.empty();
}

bool ViewerWorker::loading(std::string* stage) const {
  std::lock_guard lock(mutex_);
  if (stage && loadRunning_ && *stage != stage_) *stage = stage_;
  return loadRunning_ || load_;
}

void ViewerWorker::setStage(const char* stage) {
  std::lock_guard lock(mutex_);
  stage_ = stage;
}

void ViewerWorker::run() {
  while (true) {
    std::optional<LoadJob> load;
    std::optional<SurfaceJob> surface;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || load_ || surface_; });
      if (stop_) return;
      if (load_) {
        load.swap(load_);
        loadRunning_ = true;
        stage_ = "reading " + load->path;
      } else {
        surface.swap(surface_);
      }
      running_ = true;
    }
    WorkerResult r;
    const auto t0 = std::chrono::steady_clock::now();
    if (load) {
      r.id = load->id;
      try {
        auto data = std::make_shared<ViewerDataset>();
        data->path = load->path;
        TensorInputOptions in;
        in.layout = load->layout;
        in.quiet = true;
        in.onStage = [this](const std::string& stage) { setStage(stage.c_str()); };
        try {
          data->loaded = loadTensorInput(load->path, in);
        } catch (...) {
          rethrowWithContext("while loading " + load->path);
        }
        setStage("computing FA");
        data->fa = computeFaMap(data->loaded.field);
        setStage("preparing the FA isosurface sweeper");
        surfaces::IsosurfaceOptions io;
        io.smoothSigmaVoxels = data->buildOptions.smoothSigmaVoxels;
        io.minComponentFraction = data->buildOptions.minComponentFraction;
        io.meshSmoothIterations = data->buildOptions.meshSmoothIterations;
        data->sweeper = std::make_unique<surfaces::IsosurfaceSweeper>(data->fa, io);
        const Grid& g = data->loaded.field.grid;
        g.worldBounds(data->lo, data->hi);
        const glm::dvec3 half = 0.5 * g.spacing;
        data->lo -= half;
        data->hi += half;
        setStage("extracting the surface");
        r.kind = WorkerResult::Kind::Loaded;
        r.spec = load->first;
        try {
          r.mesh = extractViewerSurface(*data, load->first);
        } catch (...) {
          r.error = "while building the " + describeSurface(load->first) + ": " + currentExceptionMessage();
        }
        r.data = std::move(data);
      } catch (...) {
        r.kind = WorkerResult::Kind::Failed;
        r.error = currentExceptionMessage();
      }
    } else {
      r.id = surface->id;
      r.spec = surface->spec;
      try {
        // An empty FA isosurface is a normal result while sweeping, not an error.
        const ViewerDataset& d = *surface->data;
        r.mesh = surface->spec.kind == SurfaceSpec::Kind::Fa && d.sweeper
                     ? d.sweeper->extract(surface->spec.value)
                     : extractViewerSurface(d, surface->spec);
        r.kind = WorkerResult::Kind::Surface;
      } catch (...) {
        r.kind = WorkerResult::Kind::Failed;
        r.error = currentExceptionMessage();
      }
    }
    r.ms = msSince(t0);
    std::lock_guard lock(mutex_);
    results_.push_back(std::move(r));
    running_ = false;
    loadRunning_ = false;
  }
}

} // namespace dtf::app
