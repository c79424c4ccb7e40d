// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's panes over a session (ui/session/viewer_session.h, which holds the data, the surface, the
// tracts, the workers, the write policy and the error modal): one or two fabric panes (FabricRenderer each,
// the batch renderer's path), their cameras, and the tracts the session selected drawn over them
// (render/tract_layer.h under a frame budget). It performs the camera and pane actions and hands the rest of
// ui/session/actions.h to the session. It needs a current GL 4.5 context but no GLFW, so `dtfabric view`
// drives it from a window and `dtfabric bench view` from the headless context. Errors never escape: they
// become the session's error chain, which the window shows as a modal.
#pragma once

#include "io/model/image.h"
#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "render/figure_furniture.h"
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "ui/session/actions.h"
#include "ui/session/roi_outline.h"
#include "ui/session/coalescing_worker.h"
#include "ui/session/fibre_input.h"
#include "ui/session/keymap.h"
#include "ui/session/render_job.h"
#include "ui/session/viewer_profile.h"
#include "ui/session/viewer_session.h"
#include "ui/session/viewer_state.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

class ViewerScene {
public:
  // `surface`: the first surface in ui/session/surface_spec.h syntax (empty = FA isosurface at 0.25).
  explicit ViewerScene(const std::string& surface = {});
  ~ViewerScene();

  // Performs an action: cameras and panes here, the rest in the session (Screenshot and Quit are the
  // window's; they are ignored here).
  void apply(const session::Action& action);
  void applyKey(session::Key key);
  // Takes the session's finished work and uploads what changed. Call once per frame.
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
  // A 95 % cone-of-uncertainty map (degrees, io::readConeMap) that frays the threads of every pane;
  // nullopt removes it.
  // A bedpostx folder's populations keep their own cones over a fibre set (session::conesFor).
  void setUncertainty(std::optional<session::UncertaintyMap> map) {
    uncertainty_ = std::move(map);
    ++coneSerial_;
    dataChanged();
  }
  bool hasUncertainty() const { return uncertainty_.has_value(); }
  // The figure furniture over the panes as `render` draws it on a still (session::SetFurniture: the DEC
  // orientation legend, the scale bar, the tract value's colour bar where tracts are coloured by a value)
  // and the uncertainty legend, on a canvas of the scene area (scene pixels, y down). The window draws it
  // over the panes, `scale` times larger (the UI scale); screenshot-scene and layoutImage() carry it at
  // scale 1.
  void drawFurniture(render::Canvas& scene, double scale = 1) const;
  // The background on screen (session::SetBackground resolved for the data; null: none).
  const session::Background* background() const { return background_ ? &*background_ : nullptr; }
  // Renders every pane again on the next render() as if the camera had moved (benchmarks).
  void redraw() { cameraChanged(); }
  // Pane p's full-size renderer (pass timings in benchmarks).
  render::FabricRenderer& paneRenderer(int p) { return upToDate(renderers_[p], p); }

  session::ViewerSession& session() { return session_; }
  const session::ViewerSession& session() const { return session_; }
  // The background asked for (session::SetBackground as given; empty what: the default).
  const session::SetBackground& backgroundAsked() const { return backgroundAsked_; }
  const session::ViewerState& state() const { return session_.state(); }
  // No load, extraction, tract loading, selection, tracking, agreement, save or recording queued or running.
  bool settled() const {
    return session_.settled() && !recording_ && !(alongWorker_ && alongWorker_->busy()) &&
           !(profileWorker_ && profileWorker_->busy());
  }
  // Every pane reached still quality, its tracts included.
  bool converged() const;
  // Advection iterations pane p's fabric ran since it last restarted from beta (the still refinement).
  int refinedIterations(int p) const { return iterationsSinceRestart_[p]; }
  // Pane p draws the tracts: some are loaded and visible, and p is not the plain left pane of the split
  // mode "fabric | fabric + tracts".
  bool paneShowsTracts(int p) const;
  // The tract renderer (nullptr before the first tracts are shown) and the frame budget (benchmarks).
  const render::TractRenderer* tractRenderer() const { return tractRenderer_.get(); }
  // The tracts the selection draws from (grouped and coloured as chosen) and the display uploaded last.
  const Polylines* shownTracts() const { return session_.shownTracts(); }
  const render::DisplayTracts* displayedTracts() const { return uploaded_.get(); }
  const render::TractBudget& tractBudget() const { return tractBudget_; }
  int paneCount() const { return state().split && !state().ortho ? 2 : 1; }
  // Pane p's rectangle in scene pixels (x, y down, w, h) and its camera.
  std::array<int, 4> paneRect(int p) const;
  const render::Camera& camera(int p) const { return cameras_[state().linked ? 0 : p]; }
  int paneAt(double x) const;
  void setActivePane(int p) { activePane_ = p; }

  // The ortho layout (session::SetOrtho): the axial, coronal and sagittal slice panes s = 0, 1, 2 through the
  // crosshair, top left, top right and bottom left; the 3D pane (pane 0) bottom right. Slice pane s's
  // rectangle in scene pixels (x, y down, w, h) and its camera (the display views, radiological unless
  // neurological).
  std::array<int, 4> orthoRect(int s) const;
  const render::Camera& orthoCamera(int s) const { return orthoCameras_[s]; }
  // The slice pane under scene pixel (x, y down), or -1 (the 3D pane, outside, not the ortho layout).
  int orthoPaneAt(double x, double y) const;
  // Scene pixel (x, y down) of a world point in slice pane s.
  glm::dvec2 orthoPixel(int s, const glm::dvec3& world) const;
  // In the ortho layout, a click at scene pixel (x, y down) in a slice pane moves the crosshair to that point
  // of the pane's slice plane (the other panes follow to its slices); returns whether it was in one.
  bool clickAt(double x, double y);
  // The world point of slice pane s's plane under scene pixel (x, y down).
  glm::dvec3 orthoWorld(int s, double x, double y) const;
  // Slice pane s's plane (unit normal, offset: dot(n, p) + w = 0, world mm); nullopt while it has no slice.
  const std::optional<glm::vec4>& orthoPlane(int s) const { return orthoPlanes_[s]; }
  // The outline of region i of the ROI set where it cuts slice pane s, as scene pixels (x, y down) in `out`
  // (its capacity is reused): a closed polygon for a sphere or box, segments (pairs of points) for a mask
  // (session::maskOutline), told by `segments`. False when the region is hidden or misses the slice.
  bool regionOutlinePixels(int s, std::size_t i, std::vector<glm::dvec2>& out, bool* segments = nullptr) const;
  // The visible sphere or box region whose section holds scene pixel (x, y down) of a slice pane (the last
  // in the list first), or -1.
  int regionAt(double x, double y) const;
  // What a drag in slice pane s does to region i: `start` (the region when the press began) moved by the
  // world step from `from` (the press's point on the slice, orthoWorld) to scene pixel (x, y), which lies
  // in the slice's plane.
  session::RoiSet regionDragged(std::size_t i, const surfaces::Region& start, int s, const glm::dvec3& from,
                                double x, double y) const;
  // What `notches` of the wheel over scene pixel (x, y) do to the region there (regionAt): its radius or its
  // box's half-sizes scaled by 1.1 per notch about its centre (radius kept in [0.5, 200] mm). nullopt where
  // no region is.
  std::optional<session::RoiSet> regionScaled(double x, double y, double notches) const;
  // The scene as a figure, width x height of the last render(), row 0 at the top: every pane as rendered, and
  // in the ortho layout the crosshair and each slice pane's orientation letters.
  Image layoutImage() const;
  // The regions of the ROI set over 3D pane p of `img` (a layoutImage), as the window draws them.
  void drawRegions3d(Image& img, int p) const;
  // Where world points land in 3D pane p, in pixels from the pane's top-left corner (y down), for a pane of
  // w x h pixels (the window's may differ from the scene's); false behind the camera. The projection is made
  // once per pane and frame, not per point.
  struct PaneProjection {
    glm::dmat4 m{1.0};
    double w = 1, h = 1;
    bool operator()(const glm::dvec3& world, glm::dvec2& out) const {
      const glm::dvec4 c = m * glm::dvec4(world, 1.0);
      if (c.w <= 1e-9) return false;
      out = {(c.x / c.w * 0.5 + 0.5) * w, (0.5 - c.y / c.w * 0.5) * h};
      return true;
    }
  };
  PaneProjection paneProjection(int p, double w, double h) const;
  bool panePixel(int p, const glm::dvec3& world, double w, double h, glm::dvec2& out) const {
    return paneProjection(p, w, h)(world, out);
  }
  // The 3D shape of mask region r (session::maskSurface), cached by mask: it costs a pass over the voxels.
  const session::MaskSurface& maskSurface(const surfaces::Region& r) const;
  // Shows an error (outermost context first) in the modal; errorSerial() counts the errors shown so far.
  void setError(const std::string& message) { session_.setError(message); }
  std::uint64_t errorSerial() const { return session_.errorSerial(); }
  void setFrameMs(double ms) { session_.state().frameMs = ms; }
  // Meshes put on screen so far (benchmarks count sweep results with it).
  std::uint64_t meshSerial() const { return session_.meshSerial(); }
  void addRecent(const std::string& path) { session_.addRecent(path); }

  // The session's write policy (ui/session/viewer_session.h).
  bool mayWrite(const std::string& path, bool force, const session::Action& action) {
    return session_.mayWrite(path, force, action);
  }
  std::optional<session::Action> answerOverwrite(bool overwrite) {
    return session_.answerOverwrite(overwrite);
  }
  void setAskBeforeOverwrite(bool on) { session_.setAskBeforeOverwrite(on); }
  void addInput(const std::string& path) { session_.addInput(path); }
  // A GL failure (GlError: context, shaders, GPU memory, texture limits) was reported since construction.
  bool glFailed() const { return glFailed_; }
  // The data on screen (null before the first load).
  std::shared_ptr<const session::ViewerDataset> dataset() const { return session_.dataset(); }
  // Replaces the tensors on screen by `field` (same grid; the orientation check's correction, in memory).
  void replaceField(TensorField field) { session_.replaceField(std::move(field)); }

private:
  struct Recording; // a turntable being recorded (viewer.cpp)
  // Uploads the current mesh / field / fibres to `r` when it has not seen them yet (4 renderers, used as
  // needed).
  render::FabricRenderer& upToDate(std::unique_ptr<render::FabricRenderer>& r, int slot);
  // The field / fibres part of upToDate; slots 4..6 are the slice panes, 7 the recorder.
  void uploadField(render::FabricRenderer& r, int slot);
  // Ortho layout: slice indices through the crosshair, meshes rebuilt where an index changed, cameras.
  void updateOrtho();
  void renderOrtho(const render::FabricParams& params);
  // The grey beneath for the data on screen: SetBackground's choice, else a DWI's mean b=0 image in the
  // anatomy look (as `render`); re-resolved when the choice, the data or the look change.
  void resolveBackground();
  // The fabric along the tracts (session::SetFabricAlong): the proximity weight of alongSource() requested
  // from alongWorker_ when the lines or the distance change, taken when it is done.
  void updateAlong();
  // The streamlines the fabric follows and the profile measures: the ROI selection's
  // (session::RoiSelection: its indices into every loaded streamline) when a region applies, else the tracts
  // on screen (their groups), every one.
  struct TractSubset {
    std::shared_ptr<const Polylines> lines;
    std::shared_ptr<const std::vector<std::uint32_t>> which; // null: all of `lines`
    bool operator==(const TractSubset&) const = default;
  };
  TractSubset selectedTracts() const {
    const session::RoiSelection& sel = session_.roiSelection();
    if (sel.active && sel.tracts) return {sel.tracts, sel.lines ? sel.lines : kNoLines};
    return {session_.shownTractsShared(), nullptr};
  }
  static inline const std::shared_ptr<const std::vector<std::uint32_t>> kNoLines =
      std::make_shared<const std::vector<std::uint32_t>>();
  // The Profile panel (session::SetProfile): the profile of profileSource() along the chosen scalar requested
  // from profileWorker_ when the streamlines, the data or the scalar change, taken when it is done.
  void updateProfile();
  using ProfileSource = TractSubset;
  // The crosshair to the hovered node's core, else the pinned one's (nothing when neither).
  void profileCrosshair();
  void startRecording(const session::RecordMovie& request);
  void recordFrame();
  void readPane(unsigned fbo, glm::ivec2 size, const std::array<int, 4>& rect, Image& into) const;
  void setView(render::StandardView v);
  void cameraChanged();
  void dataChanged();
  render::Camera& cameraFor(int pane);
  double paneAspect(int p) const;
  // Performs the camera and pane actions; false for the session's.
  bool applyView(const session::Action& action);
  void tractFrame(int p, bool fabricChanged, bool moving);
  render::ColourMode otherColour(render::ColourMode mode) const;
  // What a tract layer draws besides the camera: the selection uploaded, the surface it is depth-tested
  // against, the width and the clip slab.
  std::uint64_t tractKey() const {
    return ((seenDisplay_ * 1000003 + session_.meshSerial()) * 1009 + session_.tractStyleSerial()) * 1013 +
           nodeColourSerial_ * 131 + static_cast<std::uint64_t>(highlightedNode() + 1);
  }
  // The Profile panel's node drawn as a band across the tracts: the hovered one, else the pinned one (-1:
  // none, or the panel is off).
  int highlightedNode() const;
  // The colours of the nodes when the tracts are coloured by the profile's value
  // (session::kProfileColouring): the profile's mean at each node through the tract colour map, over the
  // chosen range or the profile's own; recomputed when the profile or the choice changes (nodeColourSerial_),
  // set on the tract renderers.
  void updateNodeColours();
  void setNodeColours(render::TractRenderer& r) const;

  session::ViewerSession session_;
  std::array<std::unique_ptr<render::FabricRenderer>, 2> renderers_; // full size
  std::array<std::unique_ptr<render::FabricRenderer>, 2> lowRes_;    // interactive frames
  // Serials of the mesh and field each renderer holds, and whether it holds a tensor's principal directions
  // as fibres (the fibres colour mode on tensors).
  std::array<std::uint64_t, 8> meshUploaded_{}, fieldUploaded_{}, coneUploaded_{};
  std::optional<session::UncertaintyMap> uncertainty_;
  ScalarVolume cone_;                          // conesFor(uncertainty_, the data's fibres)
  std::uint64_t coneSerial_ = 0, coneBuilt_ = 0, coneField_ = 0; // cone_ is of coneBuilt_ and coneField_
  std::array<bool, 8> principalUploaded_{};
  session::SetBackground backgroundAsked_;
  std::optional<session::Background> background_;
  std::uint64_t backgroundSerial_ = 1, backgroundResolved_ = 0, backgroundField_ = 0, backgroundVersion_ = 1;
  bool backgroundAnatomy_ = false;
  std::array<std::uint64_t, 8> backgroundUploaded_{};
  struct AlongJob {
    std::shared_ptr<const Polylines> lines;
    std::shared_ptr<const std::vector<std::uint32_t>> which; // null: all of `lines`
    double mm = 2.0;
    std::uint64_t serial = 0;
  };
  struct AlongResult {
    std::shared_ptr<const ScalarVolume> weight; // null: none (an error)
    std::string error;
    std::uint64_t serial = 0;
  };
  TractSubset alongLines_;                          // of the last request (null lines: the fabric everywhere)
  double alongMm_ = 0.0;                            // of the last request
  std::uint64_t alongSerial_ = 0;                   // requests made
  std::shared_ptr<const ScalarVolume> alongWeight_; // on screen (null: the fabric everywhere)
  std::uint64_t alongVersion_ = 1;
  std::array<std::uint64_t, 8> alongUploaded_{};
  std::unique_ptr<session::CoalescingWorker<AlongJob, AlongResult>> alongWorker_; // made on first use
  ProfileSource profiled_;                                                        // of the last request
  std::shared_ptr<const session::ViewerDataset> profiledData_;
  std::string profiledScalar_;
  std::uint64_t profileSerial_ = 0; // requests made
  std::unique_ptr<session::CoalescingWorker<session::ViewerProfileJob, session::ViewerProfileResult>>
      profileWorker_;                        // made on first use
  mutable render::ValueColourBar colourBar_; // the tracts' value and range (kept: drawing it allocates nothing)
  std::optional<FibreSet> principal_; // of the field with serial principalSerial_
  std::uint64_t principalSerial_ = 0;
  bool crosshairOnMesh_ = false; // the next mesh is a load's first: a slice places the crosshair
  std::uint64_t seenLoad_ = 0, seenField_ = 0, seenMesh_ = 0, seenDisplay_ = 0; // the session's serials taken
  std::array<render::FabricRenderer*, 2> outputRenderer_{nullptr, nullptr};     // what outputFbo_ belongs to
  std::array<glm::ivec2, 2> outputSize_{};
  double interactiveScale_ = 0.5, scale_ = 0.5;
  std::array<render::Camera, 2> cameras_;
  std::array<unsigned, 2> outputFbo_{0, 0};
  std::array<bool, 2> dirty_{true, true};
  std::array<int, 2> iterationsSinceRestart_{0, 0};
  std::array<unsigned, 2> covered_{0, 0};
  bool hasField_ = false; // false after a GL failure until new data arrive
  bool interacting_ = false;
  int activePane_ = 0;
  int width_ = 1, height_ = 1;
  std::chrono::steady_clock::time_point lastMotion_{};

  std::unique_ptr<render::TractRenderer> tractRenderer_;  // created with the first selection result
  std::shared_ptr<const render::DisplayTracts> uploaded_; // what tractRenderer_ holds
  // Per pane, one layer for full-size and one for interactive frames (as the renderers: switching between
  // the two sizes re-creates no targets); tractLayer_[p] is the one pane p drew with last.
  std::array<std::unique_ptr<render::TractLayer>, 4> tractLayers_;
  std::array<render::TractLayer*, 2> tractLayer_{nullptr, nullptr};
  std::array<std::uint64_t, 2> tractKeys_{}; // key pane p's layer last drew with
  std::array<bool, 2> tractsShown_{false, false};
  render::TractBudget tractBudget_;
  bool glFailed_ = false;

  // Ortho layout.
  std::array<std::unique_ptr<render::FabricRenderer>, 3> orthoRenderers_;
  std::array<Mesh, 3> orthoMeshes_;
  std::array<render::Camera, 3> orthoCameras_;
  std::array<int, 3> orthoBuilt_{-1, -1, -1}; // slice index of each mesh (-1: none)
  std::array<std::optional<glm::vec4>, 3> orthoPlanes_;      // each mesh's plane
  std::unique_ptr<render::TractRenderer> orthoTracts_;        // every tract drawn, for the slice panes
  std::shared_ptr<const render::DisplayTracts> orthoUploaded_; // what orthoTracts_ holds
  std::array<glm::vec4, render::kMaxTractNodeColours> nodeColours_{}; // of nodeColourCount_ nodes
  std::size_t nodeColourCount_ = 0;                                   // 0: not coloured by the profile
  std::uint64_t nodeColourSerial_ = 0, profileResults_ = 0, nodeColoursFor_ = ~0ull;
  std::optional<std::pair<double, double>> nodeColourRange_;
  std::uint64_t orthoTractKey_ = 0;                           // the tract style the slice panes drew with
  mutable std::vector<glm::dvec3> outlineWorld_;              // regionOutlinePixels' scratch
  mutable std::vector<unsigned char> outlineSamples_;         // its mask lattice
  // Mask outlines by mask and slice plane: a mask's bounds and lattice cost a pass over its voxels, too much
  // for every frame; the outline changes only with the slice or the mask.
  struct MaskOutline {
    std::shared_ptr<const MaskVolume> mask; // held, so its address is not reused while cached
    glm::vec4 plane{0.0f};
    bool cuts = false;
    std::vector<glm::dvec3> segments;
  };
  mutable std::vector<MaskOutline> maskOutlines_; // at most kMaskOutlineCache, the oldest replaced
  struct MaskShape {
    std::shared_ptr<const MaskVolume> mask; // held, as in MaskOutline
    session::MaskSurface surface;
  };
  mutable std::vector<MaskShape> maskShapes_; // at most kMaskOutlineCache, the oldest replaced
  mutable std::size_t nextMaskShape_ = 0;
  mutable std::size_t nextMaskOutline_ = 0;
  static constexpr std::size_t kMaskOutlineCache = 12;
  std::array<bool, 3> orthoDirty_{true, true, true}, orthoMeshNew_{false, false, false};
  std::array<int, 3> orthoIterations_{0, 0, 0};
  std::array<unsigned, 3> orthoCovered_{0, 0, 0};
  std::uint64_t orthoField_ = 0; // the field serial the meshes were cut from
  std::array<int, 3> orthoCameraKey_{0, 0, -1}; // width, height, neurological the cameras were made for

  std::unique_ptr<Recording> recording_;
  std::unique_ptr<render::FabricRenderer> recorder_;
};

// Camera files: a small text format (eye, target, up, projection); throws InputError on a bad file.
void writeCameraFile(const std::string& path, const render::Camera& camera);
render::Camera readCameraFile(const std::string& path);

} // namespace dtf::app
