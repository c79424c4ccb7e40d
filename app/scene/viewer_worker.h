// The viewer's background thread: loading (and fitting) tensor data and extracting surfaces, so the window
// never blocks. Requests coalesce: a new surface request replaces one that has not
// started, so dragging the FA slider costs one extraction per result the user can see. The FA isosurface
// sweeper is prepared once per loaded field and used only on this thread (it is thread-compatible, not
// thread-safe). Results are polled by the GUI thread.
#pragma once

#include "app/scene/surface_spec.h"
#include "io/model/geometry.h"
#include "io/model/volume.h"
#include "io/tensor_io.h"
#include "surfaces/isosurface.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace dtf::app {

// A loaded tensor volume with what the viewer derives from it once.
struct ViewerDataset {
  std::string path;
  io::LoadedTensors loaded;
  ScalarVolume fa;
  std::shared_ptr<surfaces::IsosurfaceSweeper> sweeper; // FA isosurfaces with the CLI's build options (shared by
                                                        // a copy whose tensors were turned: the same FA)
  SurfaceBuildOptions buildOptions;
  glm::dvec3 lo{0.0}, hi{0.0}; // world bounds of the grid (voxel corners), mm
};

struct WorkerResult {
  enum class Kind { Loaded, Surface, Failed } kind = Kind::Failed;
  std::uint64_t id = 0;                      // the request's id
  std::shared_ptr<const ViewerDataset> data; // Loaded
  Mesh mesh;                                 // Loaded and Surface; empty: no surface at this FA
  SurfaceSpec spec;                          // the surface extracted
  std::string error;                         // Failed; for Loaded, why the first surface failed
  double ms = 0;                             // work time
};

class ViewerWorker {
public:
  ViewerWorker();
  // Finishes the running job (extractions are not interruptible) and joins.
  ~ViewerWorker();
  ViewerWorker(const ViewerWorker&) = delete;
  ViewerWorker& operator=(const ViewerWorker&) = delete;

  // Loads `path` (tensor volume or DWI) and extracts `first` from it.
  void requestLoad(std::uint64_t id, const std::string& path, io::TensorLayout layout,
                   const SurfaceSpec& first);
  // Extracts `spec` from `data`; replaces a surface request that has not started yet.
  void requestSurface(std::uint64_t id, std::shared_ptr<const ViewerDataset> data, const SurfaceSpec& spec);
  // Takes the oldest finished result, if any.
  bool poll(WorkerResult& out);
  // True while a request is queued or running.
  bool busy() const;
  // True while a load is queued or running; `stage` describes its current step.
  bool loading(std::string* stage = nullptr) const;

private:
  struct LoadJob {
    std::uint64_t id;
    std::string path;
    io::TensorLayout layout;
    SurfaceSpec first;
  };
  struct SurfaceJob {
    std::uint64_t id;
    std::shared_ptr<const ViewerDataset> data;
    SurfaceSpec spec;
  };
  void run();
  void setStage(const char* stage);

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<LoadJob> load_;
  std::optional<SurfaceJob> surface_;
  std::deque<WorkerResult> results_;
  bool running_ = false, loadRunning_ = false, stop_ = false;
  std::string stage_;
  std::thread thread_;
};

// Extracts `spec` from a loaded dataset (FA isosurfaces through its sweeper). Throws InputError when the
// surface is empty or cannot be built.
Mesh extractViewerSurface(const ViewerDataset& data, const SurfaceSpec& spec);

} // namespace dtf::app
