// SPDX-License-Identifier: GPL-3.0-or-later
// The session's surface work on a CoalescingWorker (ui/session/coalescing_worker.h): loading (and fitting)
// tensor data and extracting surfaces, so the window never blocks. A new surface request replaces one that
// has not started, so dragging the FA slider costs one extraction per result the user can see; a load drops
// the surface requests waiting for the data it replaces and runs first. The FA isosurface sweeper is
// prepared once per loaded field and used only on the worker's thread (it is thread-compatible, not
// thread-safe). Results are polled by the GUI thread.
#pragma once

#include "ui/session/coalescing_worker.h"
#include "ui/session/surface_spec.h"
#include "io/formats/fibre_io.h"
#include "io/model/geometry.h"
#include "io/model/volume.h"
#include "io/formats/tensor_io.h"
#include "surfaces/isosurface.h"

#include <cstdint>
#include <memory>
#include <string>
#include <variant>

namespace dtf::session {

// A loaded tensor volume or fibre set with what the viewer derives from it once.
struct ViewerDataset {
  std::string path;
  io::LoadedTensors
      loaded;      // fibre sets: the paired tensor, else the fibres' carrier field (surface clipping)
  ScalarVolume fa; // empty for a fibre set without FA (no paired tensor, none in the file)
  std::shared_ptr<surfaces::IsosurfaceSweeper> sweeper; // FA isosurfaces with the CLI's build options (shared
                                                        // by a copy whose tensors were turned: the same FA)
  // Slices and planes over the whole grid, as `render` builds them under a background: the anatomy (a DWI's
  // mean b=0, --background) shows around and inside the data; without one the renderer's smooth data edge
  // outlines the fabric as on a clipped slice (outside it the composite writes nothing).
  SurfaceBuildOptions buildOptions{.clipToData = false, .dataEdgeCells = true};
  glm::dvec3 lo{0.0}, hi{0.0}; // world bounds of the grid (voxel corners), mm
  // Fibre sets (ui/session/fibre_input.h): the fibres as read, whether a tensor is paired, where FA comes
  // from.
  std::shared_ptr<const io::LoadedFibres> fibres;
  bool pairedTensor = false;
  std::string faSource;
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
  // Finishes the running job (loads and extractions are not interruptible) and joins.
  ~ViewerWorker();
  ViewerWorker(const ViewerWorker&) = delete;
  ViewerWorker& operator=(const ViewerWorker&) = delete;

  // Loads `path` (tensor volume, DWI, or fibre set with the optional tensor `tensorPath`, as `dtfabric
  // render` reads them; `layout`: auto, a tensor or a fibre layout) and extracts `first` from it. With
  // `sliceWithoutFa`, a fibre set without FA starts on the middle axial slice instead of an FA isosurface
  // (else that surface is refused as it is by `render`).
  void requestLoad(std::uint64_t id, const std::string& path, const std::string& layout,
                   const std::string& tensorPath, const SurfaceSpec& first, bool sliceWithoutFa = true);
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
    std::string path, layout, tensorPath;
    SurfaceSpec first;
    bool sliceWithoutFa = true;
  };
  struct SurfaceJob {
    std::uint64_t id;
    std::shared_ptr<const ViewerDataset> data;
    SurfaceSpec spec;
  };
  using Job = std::variant<LoadJob, SurfaceJob>;
  enum Lane : std::size_t { kLoad = 0, kSurface = 1 };
  static WorkerResult load(const LoadJob& job, WorkContext& context);
  static WorkerResult surface(const SurfaceJob& job);

  CoalescingWorker<Job, WorkerResult> worker_;
};

// Extracts `spec` from a loaded dataset (FA isosurfaces through its sweeper). Throws InputError when the
// surface is empty or cannot be built, UsageError when it needs FA or tensor directions a fibre set lacks.
Mesh extractViewerSurface(const ViewerDataset& data, const SurfaceSpec& spec);

} // namespace dtf::session
