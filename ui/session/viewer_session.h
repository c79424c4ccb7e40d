// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's session without a window or GL: the loaded data with its layout diagnosis (tensors, a DWI
// fitted on load, or a fibre set with an optional paired tensor), the surface spec and its extraction, the
// tracts and their selection for the surface, the workers doing the long work (ui/session/viewer_worker.h,
// ui/session/tract_worker.h), the write/overwrite policy for outputs, and the error modal's state. It
// performs the actions of ui/session/actions.h that concern these; cameras, panes and drawing are the front
// end's (app/viewer/viewer.h), which reads what to draw here and learns of changes by the serials. Errors
// never escape: they become the error chain in state().
#pragma once

#include "io/model/geometry.h"
#include "render/tract_renderer.h"
#include "ui/session/actions.h"
#include "ui/session/roi_selection.h"
#include "ui/session/roi_worker.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tract_worker.h"
#include "ui/session/viewer_state.h"
#include "ui/session/viewer_worker.h"

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dtf::session {

class ViewerSession {
public:
  // `surface`: the first surface in ui/session/surface_spec.h syntax (empty = FA isosurface at 0.25).
  explicit ViewerSession(const std::string& surface = {});
  ~ViewerSession();
  ViewerSession(const ViewerSession&) = delete;
  ViewerSession& operator=(const ViewerSession&) = delete;

  // Performs the session's part of an action: loading, surfaces, fabric parameters, tracts, outputs of
  // tracts, errors. Camera, pane, screenshot, camera-file, overwrite-answer and quit actions are left to the
  // front end (nothing happens here). A failure becomes the error modal.
  void apply(const Action& action);
  // Takes finished work from the workers. Call once per frame.
  void update();

  ViewerState& state() { return state_; }
  const ViewerState& state() const { return state_; }
  // No load, extraction, tract loading, selection, tracking, agreement or save queued or running.
  bool settled() const;

  // Shows an error (outermost context first) in the modal; errorSerial() counts the errors shown so far.
  void setError(const std::string& message);
  std::uint64_t errorSerial() const { return errorSerial_; }
  void addRecent(const std::string& path);

  // Output files (screenshots, camera files, tracts). A file this session read (volume and its gradient
  // tables, a paired tensor, tracts, meshes, the script) is never replaced, whatever `force` says; an
  // existing file is replaced only with `force`. Otherwise the refusal goes to the error modal, or, when
  // asking is on (the GUI, not a script), `action` waits for the overwrite prompt (state().overwritePath).
  // Returns whether to write now.
  bool mayWrite(const std::string& path, bool force, const Action& action);
  // Closes the overwrite prompt: the waiting action with force set when `overwrite`, else nothing.
  std::optional<Action> answerOverwrite(bool overwrite);
  void setAskBeforeOverwrite(bool on) { askBeforeOverwrite_ = on; }
  // Records a file read outside the session's actions (the script) as an input.
  void addInput(const std::string& path);
  const std::vector<std::string>& inputs() const { return inputs_; }

  // The data on screen (null before the first load).
  std::shared_ptr<const ViewerDataset> dataset() const { return data_; }
  // Replaces the tensors on screen by `field` (same grid; the orientation check's correction, in memory):
  // FA and its isosurface sweeper are kept, the fabric restarts and the surface is extracted again.
  void replaceField(TensorField field);
  // What a saved session needs: the request of the data on screen (path, layout, paired tensor), the surface
  // on screen as a spec (a slice with its index), the tract file on screen (empty: none, or tracked in the
  // viewer) and the tract choice in effect.
  const LoadFile& loadedRequest() const { return loaded_; }
  SurfaceSpec surfaceSpec() const { return currentSpec(); }
  const std::string& tractsFile() const { return tractsFile_; }
  const SetTractGroups& tractGroups() const { return tractGroups_; }
  const SetTractColour& tractColour() const { return tractColour_; }
  // The view a new load starts from (the standard view of its surface).
  render::StandardView homeView() const { return homeView_; }

  // What the front end draws, with serials that change when it must take it again: loads applied (set the
  // home view), the field (tensors or fibres, upload), the surface (upload; counts as motion).
  std::uint64_t loadSerial() const { return loadSerial_; }
  std::uint64_t fieldSerial() const { return fieldSerial_; }
  std::uint64_t meshSerial() const { return meshSerial_; }
  const std::shared_ptr<const Mesh>& mesh() const { return mesh_; }
  glm::vec3 meshCentre() const {
    return meshCentre_;
  } // centre of the surface's bounds (the clip slab's anchor)

  // The tracts: all points (analysis and saving), those the selection draws from (grouped and coloured as
  // chosen), and the selection's display for the surface on screen (display decimation and levels of
  // detail; displaySerial changes with every selection result). On a planar surface the selection is every
  // tract in a slab around `tractsPlane`.
  const Polylines* tracts() const { return tracts_.get(); }
  const Polylines* shownTracts() const { return shownTracts_ ? shownTracts_.get() : tracts_.get(); }
  // The same, shared (for work off the UI thread); null without tracts.
  std::shared_ptr<const Polylines> shownTractsShared() const { return shownTracts_ ? shownTracts_ : tracts_; }
  // Redoes the colouring and group choice in effect (and the tracts' display): the Profile panel turned on
  // or off adds or drops each point's node (render::kTractDisplayNode).
  // The size past which a colouring or group choice, dimming or the profile's nodes are made off the UI
  // thread (points of the tracts copied): kTractChoiceSyncPoints, lowered by tests.
  void setTractChoiceSyncPoints(std::size_t points) { choiceSyncPoints_ = points; }
  void reapplyTractChoice() {
    if (!tracts_) return;
    applyTractChoice(tractColour_, tractGroups_);
    requestSelection();
  }
  const std::shared_ptr<const render::DisplayTracts>& tractDisplay() const { return display_; }
  std::uint64_t displaySerial() const { return displaySerial_; }
  // The display of every tract drawn (after the ROI selection and the group choice), whatever the surface:
  // what the ortho layout's slice panes draw in a slab around their planes. Changes with displaySerial.
  const std::shared_ptr<const render::DisplayTracts>& tractDisplayAll() const { return allDisplay_; }
  bool tractsSlab() const { return tractsSlab_; }
  glm::vec4 tractsPlane() const { return tractsPlane_; }
  // The ROI selection of the tracts (ui/session/roi_selection.h, which says how to read it): UI thread only.
  const RoiSelection& roiSelection() const { return roi_; }
  // Counts changes of the tract width and the clip slab.
  std::uint64_t tractStyleSerial() const { return tractStyleSerial_; }

  // The fabric parameters for the surface on screen (paramsOnSurface: on an FA isosurface the anatomy look's
  // fabric is opaque).
  render::FabricParams fabricOnScreen() const;

  // Fills state().probe for the surface point `world` (world RAS mm): the voxel, its tensor and its fibres,
  // and the status bar's text. clearProbe(): the cursor is not on the surface.
  void probeAt(const glm::dvec3& world);
  void clearProbe();

private:
  void loadFile(const LoadFile& a);
  void requestSurface();
  void applySpec(const SurfaceSpec& spec);
  SurfaceSpec currentSpec() const;
  void onResult(WorkerResult& r);
  void setMesh(Mesh&& mesh);
  void countFibres();
  // meanLengthMm: the lines' mean length when already known (computed off the UI thread).
  void setTracts(std::shared_ptr<const Polylines> lines, const std::string& label,
                 std::optional<double> meanLengthMm = std::nullopt);
  void requestSelection(std::size_t pointCap = kNearSurfacePointCap);
  // Applies the chosen groups and colouring to tracts_ into shownTracts_ (what the selection draws) and
  // the Tracts panel's state; throws (leaving the previous choice on screen) for a missing name or
  // without tracts.
  void applyTractChoice(const SetTractColour& colour, const SetTractGroups& groups);
  void showApplied(const TractColouringApplied& applied); // the colour bar's range and the log line
  void onTractResult(TractResult& r);
  void startTracking(const TrackRequest& request);
  void startAgreement(const ComputeAgreement& a);
  void saveTracts(const SaveTracts& a);
  // The ROI selection: a job for the region set in state_.roiSet, its result, the region set's actions.
  void requestRoi();
  void onRoiResult(RoiResult& r);
  void applyRoi(const Action& action);

  ViewerState state_;
  std::shared_ptr<const ViewerDataset> data_;
  std::string initialSurface_;
  SurfaceSpec otherSpec_; // the spec behind SurfaceKind::Fibre / Other
  std::uint64_t nextId_ = 1, latestLoad_ = 0, latestSurface_ = 0;
  std::uint64_t loadSerial_ = 0, fieldSerial_ = 0, meshSerial_ = 0, errorSerial_ = 0;
  std::shared_ptr<const Mesh> mesh_; // on screen; shared with the tract jobs
  glm::vec3 meshCentre_{0.0f};
  render::StandardView homeView_ = render::StandardView::Superior;
  std::chrono::steady_clock::time_point busySince_{};
  LoadFile requested_, loaded_; // the latest load asked for, and the one on screen
  std::string tractsFile_;      // the file of the tracts on screen; empty: none, or tracked

  struct LoadedTracts {
    std::shared_ptr<const Polylines> lines;
    double meanLengthMm = 0;
  };
  std::future<LoadedTracts> tractsLoading_; // loading on its own thread
  std::string pendingTractPath_;
  std::shared_ptr<const Polylines> tracts_;      // every point: analysis and saving use these
  std::shared_ptr<const Polylines> shownTracts_; // tracts_ filtered by group and coloured: what is drawn
  // A choice whose tracts the worker makes (more than choiceSyncPoints_ points to copy), until its selection
  // result comes; smaller ones are made at once.
  std::shared_ptr<const TractChoice> pendingChoice_;
  std::size_t choiceSyncPoints_ = kTractChoiceSyncPoints;
  SetTractColour tractColour_;                   // the choice in effect
  SetTractGroups tractGroups_;
  std::uint64_t tractsSerial_ = 0, latestSelection_ = 0, latestTracking_ = 0, latestAgreement_ = 0;
  std::shared_ptr<const render::DisplayTracts> display_; // the latest selection's display
  std::shared_ptr<const render::DisplayTracts> allDisplay_; // ... and of every tract
  std::uint64_t displaySerial_ = 0, tractStyleSerial_ = 0;
  bool tractsSlab_ = false;
  glm::vec4 tractsPlane_{0, 0, 1, 0};
  RoiSelection roi_; // the ROI selection on screen (roiSelection())
  // Its streamlines as drawn (the others hidden): their display decimation, made by the ROI worker.
  std::shared_ptr<const Polylines> roiSubset_;
  std::uint64_t roiTractsSerial_ = 0, latestRoi_ = 0; // the tract set the ROI worker indexes; its latest job
  // The surface on screen is curved and tracts are drawn near it (the near-surface rule applies); the ROI
  // subset the last request asked for keeps whole streamlines for it (RoiJob::subsetWholeLines).
  bool nearRule_ = false, roiWholeLines_ = false;
  // Asks for the ROI subset again when the surface's rule changed what it must hold.
  void reselectForSurface();
  std::optional<ComputeAgreement> pendingAgreement_; // waits for the surface or tracts on their way

  std::vector<std::string> inputs_;        // files read so far: never written (mayWrite)
  std::optional<Action> pendingOverwrite_; // waits for the overwrite prompt
  bool askBeforeOverwrite_ = true;

  // Last: their threads are joined before the members their jobs refer to go.
  ViewerWorker worker_;
  TractWorker tractWorker_;
  RoiWorker roiWorker_;
};

// The status bar's and the script's text for a probed voxel: "voxel I J K, FA F, e1 X Y Z, lambda L1 L2 L3"
// for a tensor, then "; fibres: (X Y Z) amplitude A (R%)[, ...]" for a fibre set, each fibre below the
// threshold or beyond the third marked "not drawn".
std::string describeProbe(const ProbeInfo& probe);

// The mean arc length of the lines in mm (0 without lines): the Tracts panel's statistic.
double meanLineLengthMm(const Polylines& lines);

} // namespace dtf::session
