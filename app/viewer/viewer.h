// The viewer's scene, separate from the window: the loaded data, the surface on screen, one or two fabric
// panes (FabricRenderer each, the batch renderer's path), their cameras, the tracts drawn over them
// (render/tract_layer.h under a frame budget; selection, tracking, agreement and saving on the
// app/scene/tract_worker.h threads), and the actions of ui/actions.h applied to them. It needs a current GL 4.5
// context but no GLFW, so `dtfabric view` drives it from a window and `dtfabric bench view` from the
// headless context. Errors never escape: they become the error chain in state(), which the window shows as
// a modal.
#pragma once

#include "app/scene/surface_spec.h"
#include "app/scene/tract_worker.h"
#include "app/scene/viewer_worker.h"
#include "io/model/image.h"
#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "ui/actions.h"
#include "ui/keymap.h"
#include "ui/viewer_state.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

class ViewerScene {
public:
  // `surface`: the first surface in app/scene/surface_spec.h syntax (empty = FA isosurface at 0.25).
  explicit ViewerScene(const std::string& surface = {});
  ~ViewerScene();

  // Performs an action (Screenshot and Quit are the window's; they are ignored here).
  void apply(const ui::Action& action);
  void applyKey(ui::Key key);
  // Takes finished work from the worker thread and uploads it. Call once per frame.
  void update();
  // Renders the panes for a scene area of width x height pixels: interactive frames while the camera moves
  // or the data change, more iterations per frame when still, nothing once converged.
  void render(int width, int height);
  // Copies the panes into draw framebuffer `fbo` with the scene's lower-left corner at (x, y) (GL pixels).
  void present(unsigned fbo, int x, int y);
  // The surface point under pixel (x, y) of the scene area (y down), into state().probe.
  void probe(double x, double y);
  // Marks the camera as moving (mouse held) so frames stay interactive.
  void setInteracting(bool on) { interacting_ = on; }
  // Interactive frames render at a fraction of the pane size (noise and step scaled with it, so the fabric
  // keeps its size on screen) and are magnified by the blit; still frames are full size. The fraction adapts
  // to the frame time (setFrameMs) between 1/4 and `s`, in steps of 1/8 so targets are rarely re-created.
  // 1 = off.
  void setInteractiveScale(double s) { interactiveScale_ = scale_ = std::clamp(s, 0.25, 1.0); }
  // Renders every pane again on the next render() as if the camera had moved (benchmarks).
  void redraw() { cameraChanged(); }
  // Pane p's full-size renderer (pass timings in benchmarks).
  render::FabricRenderer& paneRenderer(int p) { return upToDate(renderers_[p], p); }

  const ui::ViewerState& state() const { return state_; }
  // No load, extraction, tract loading, selection, tracking, agreement or save queued or running.
  bool settled() const;
  // Every pane reached still quality, its tracts included.
  bool converged() const;
  // Pane p draws the tracts: some are loaded and visible, and p is not the plain left pane of the split
  // mode "fabric | fabric + tracts".
  bool paneShowsTracts(int p) const;
  // The tract renderer (nullptr before the first tracts are shown) and the frame budget (benchmarks).
  const render::TractRenderer* tractRenderer() const { return tractRenderer_.get(); }
  // The tracts the selection draws from (grouped and coloured as chosen) and the display uploaded last.
  const Polylines* shownTracts() const { return shownTracts_ ? shownTracts_.get() : tracts_.get(); }
  const render::DisplayTracts* displayedTracts() const { return uploaded_.get(); }
  const render::TractBudget& tractBudget() const { return tractBudget_; }
  int paneCount() const { return state_.split ? 2 : 1; }
  // Pane p's rectangle in scene pixels (x, y down, w, h) and its camera.
  std::array<int, 4> paneRect(int p) const;
  const render::Camera& camera(int p) const { return cameras_[state_.linked ? 0 : p]; }
  int paneAt(double x) const;
  void setActivePane(int p) { activePane_ = p; }
  // Shows an error (outermost context first) in the modal; errorSerial() counts the errors shown so far.
  void setError(const std::string& message);
  std::uint64_t errorSerial() const { return errorSerial_; }
  void setFrameMs(double ms) { state_.frameMs = ms; }
  // Meshes put on screen so far (benchmarks count sweep results with it).
  std::uint64_t meshSerial() const { return meshSerial_; }
  void addRecent(const std::string& path);

  // Output files (screenshots, camera files). A file this session read (volume and its gradient tables,
  // tracts, meshes, the script) is never replaced, whatever `force` says; an existing file is replaced only
  // with `force`. Otherwise the refusal goes to the error modal, or, when asking is on (the GUI, not a
  // script), `action` waits for the overwrite prompt (state().overwritePath). Returns whether to write now.
  bool mayWrite(const std::string& path, bool force, const ui::Action& action);
  // Closes the overwrite prompt: the waiting action with force set when `overwrite`, else nothing.
  std::optional<ui::Action> answerOverwrite(bool overwrite);
  void setAskBeforeOverwrite(bool on) { askBeforeOverwrite_ = on; }
  // Records a file read outside the scene's actions (the script) as an input.
  void addInput(const std::string& path);
  // A GL failure (GlError: context, shaders, GPU memory, texture limits) was reported since construction.
  bool glFailed() const { return glFailed_; }
  // The data on screen (null before the first load).
  std::shared_ptr<const ViewerDataset> dataset() const { return data_; }
  // Replaces the tensors on screen by `field` (same grid; the orientation check's correction, in memory):
  // FA and its isosurface sweeper are kept, the fabric restarts and the surface is extracted again.
  void replaceField(TensorField field);

private:
  void loadFile(const ui::LoadFile& a);
  void requestSurface();
  void applySpec(const SurfaceSpec& spec);
  SurfaceSpec currentSpec() const;
  void onResult(WorkerResult& r);
  void setMesh(Mesh&& mesh);
  // Uploads the current mesh / field to `r` when it has not seen them yet (4 renderers, used as needed).
  render::FabricRenderer& upToDate(std::unique_ptr<render::FabricRenderer>& r, int slot);
  void setView(render::StandardView v);
  void cameraChanged();
  void dataChanged();
  render::Camera& cameraFor(int pane);
  double paneAspect(int p) const;
  // Tracts: the set on screen (`label` names it in the panel), the selection for the current surface,
  // worker results, one frame of pane p's tract layer, and the panel's long actions.
  void setTracts(std::shared_ptr<const Polylines> lines, const std::string& label);
  void requestSelection();
  // Applies the chosen groups and colouring to tracts_ into shownTracts_ (what the selection draws) and
  // the Tracts panel's state; throws (leaving the previous choice on screen) for a missing name or
  // without tracts.
  void applyTractChoice(const ui::SetTractColour& colour, const ui::SetTractGroups& groups);
  void onTractResult(TractResult& r);
  void tractFrame(int p, bool fabricChanged, bool moving);
  void startTracking(const ui::TrackRequest& request);
  void startAgreement(const ui::ComputeAgreement& a);
  void saveTracts(const ui::SaveTracts& a);
  // What a tract layer draws besides the camera: the selection uploaded, the surface it is depth-tested
  // against, the width and the clip slab.
  std::uint64_t tractKey() const {
    return (displaySerial_ * 1000003 + meshSerial_) * 1009 + tractStyleSerial_;
  }

  ui::ViewerState state_;
  ViewerWorker worker_;
  std::shared_ptr<const ViewerDataset> data_;
  std::string initialSurface_;
  SurfaceSpec otherSpec_; // the spec behind SurfaceKind::Fibre / Other
  std::uint64_t nextId_ = 1, latestLoad_ = 0, latestSurface_ = 0;
  std::array<std::unique_ptr<render::FabricRenderer>, 2> renderers_; // full size
  std::array<std::unique_ptr<render::FabricRenderer>, 2> lowRes_;    // interactive frames
  std::shared_ptr<const Mesh> mesh_; // on screen; uploaded to renderers lazily, shared with tract jobs
  std::array<std::uint64_t, 4> meshUploaded_{}, fieldUploaded_{}; // serials each renderer holds
  std::uint64_t fieldSerial_ = 0;
  std::array<render::FabricRenderer*, 2> outputRenderer_{nullptr, nullptr}; // what outputFbo_ belongs to
  std::array<glm::ivec2, 2> outputSize_{};
  double interactiveScale_ = 0.5, scale_ = 0.5;
  std::future<Polylines> tractsLoading_; // loading on its own thread
  std::string pendingTractPath_;
  std::array<render::Camera, 2> cameras_;
  std::array<unsigned, 2> outputFbo_{0, 0};
  std::array<bool, 2> dirty_{true, true};
  std::array<int, 2> iterationsSinceRestart_{0, 0};
  std::array<unsigned, 2> covered_{0, 0};
  bool hasMesh_ = false, hasField_ = false;
  bool interacting_ = false;
  int activePane_ = 0;
  render::StandardView homeView_ = render::StandardView::Superior;
  int width_ = 1, height_ = 1;
  std::uint64_t errorSerial_ = 0, meshSerial_ = 0;
  std::uint64_t tractStyleSerial_ = 0; // counts changes of the tract width and clip slab
  glm::vec3 meshCentre_{0.0f}; // centre of the surface's bounds: where the tracts' clip slab is anchored
  std::chrono::steady_clock::time_point lastMotion_{}, busySince_{};

  TractWorker tractWorker_;
  std::shared_ptr<const Polylines> tracts_; // every point: analysis and saving use these
  std::shared_ptr<const Polylines> shownTracts_; // tracts_ filtered by group and coloured: what is drawn
  ui::SetTractColour tractColour_;               // the choice in effect
  ui::SetTractGroups tractGroups_;
  std::uint64_t tractsSerial_ = 0, latestSelection_ = 0, latestTracking_ = 0, latestAgreement_ = 0;
  std::unique_ptr<render::TractRenderer> tractRenderer_;  // created with the first selection result
  std::shared_ptr<const render::DisplayTracts> uploaded_; // what tractRenderer_ holds
  std::uint64_t displaySerial_ = 0;                       // changes with every selection result
  bool tractsSlab_ = false;
  glm::vec4 tractsPlane_{0, 0, 1, 0};
  // Per pane, one layer for full-size and one for interactive frames (as the renderers: switching between
  // the two sizes re-creates no targets); tractLayer_[p] is the one pane p drew with last.
  std::array<std::unique_ptr<render::TractLayer>, 4> tractLayers_;
  std::array<render::TractLayer*, 2> tractLayer_{nullptr, nullptr};
  std::array<std::uint64_t, 2> tractKeys_{}; // key pane p's layer last drew with
  std::array<bool, 2> tractsShown_{false, false};
  render::TractBudget tractBudget_;
  std::optional<ui::ComputeAgreement> pendingAgreement_; // waits for the surface or tracts on their way
  std::vector<std::string> inputs_;                      // files read so far: never written (mayWrite)
  std::optional<ui::Action> pendingOverwrite_;           // waits for the overwrite prompt
  bool askBeforeOverwrite_ = true, glFailed_ = false;
};

// Camera files: a small text format (eye, target, up, projection); throws InputError on a bad file.
void writeCameraFile(const std::string& path, const render::Camera& camera);
render::Camera readCameraFile(const std::string& path);

} // namespace dtf::app
