// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's state as the panels see it: a plain snapshot the session (ui/session/viewer_session.h) and the
// viewer keep up to date and hand to ui/panels.h by const reference each frame. Strings here change only when
// the data or the surface change, so drawing the panels from it does not allocate.
#pragma once

#include "io/model/fibre_set.h"
#include "render/camera.h"
#include "render/fabric_params.h"
#include "surfaces/selection/regions.h"
#include "ui/session/actions.h"

#include <array>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace dtf::session {

// Facts about the loaded tensor volume (Data panel).
struct DataInfo {
  std::string path;
  std::string layout;       // layout used, e.g. "fsl"
  std::string layoutReason; // why it was chosen
  std::string orientation;  // e.g. "LAS"
  glm::ivec3 dims{0};
  glm::dvec3 spacing{0.0};
  std::size_t validVoxels = 0;
  std::vector<std::string> warnings;
};

// The fibre set on screen (Fibres panel); `present` false: the data are tensors.
struct FibreInfo {
  bool present = false;
  std::string path, layout, layoutReason; // the file, its fibre layout and why it was chosen
  std::string faSource;                   // where FA comes from (a paired tensor, the file); empty: no FA
  int slots = 0;                          // fibres per voxel the file holds
  std::size_t voxels = 0;                 // voxels with at least one fibre
  // Voxels whose populations drawn at the current threshold number 1, 2, 3 (the fabric weaves at most the
  // first three of each voxel), counted at `threshold`.
  std::array<std::size_t, 3> populations{0, 0, 0};
  float threshold = 0;
};

// One fibre of the voxel under the cursor.
struct ProbeFibre {
  glm::vec3 direction{0.0f}; // unit, world RAS
  float amplitude = 0;       // as the file holds it (peak amplitude, volume fraction)
  float relative = 0;        // amplitude / the voxel's strongest
  bool drawn = false;        // at or above the fibre threshold, among the first three
};

// The voxel under the mouse cursor (status bar).
struct ProbeInfo {
  bool onSurface = false; // the cursor is over the rendered surface
  bool inData = false;    // ... and inside the tensor grid with a valid tensor
  glm::dvec3 world{0.0};  // world RAS mm
  glm::ivec3 voxel{0};    // nearest voxel index
  double fa = 0;
  glm::dvec3 eigenvalues{0.0}; // mm^2/s, descending
  glm::dvec3 e1{0.0};          // principal direction, world RAS
  bool hasTensor = false;      // fa, eigenvalues and e1 hold the voxel's tensor (a fibre set without a paired
                               // tensor has none)
  std::vector<ProbeFibre> fibres; // fibre sets: the voxel's fibres, strongest first
  std::string text;               // the status bar's line for all of the above
};

struct ViewerState {
  bool hasData = false;
  DataInfo data;
  FibreInfo fibres;
  std::vector<std::string> recent; // most recent first

  SurfaceKind surface = SurfaceKind::FaIsosurface;
  double faThreshold = 0.25;
  std::array<int, 3> slice{0, 0, 0};      // axial, coronal, sagittal indices
  std::array<int, 3> sliceCount{1, 1, 1}; // slices along each axis
  std::string surfaceText;                // description of the mesh on screen
  std::size_t triangles = 0;
  bool surfacePending = false;
  // Seed line of the fibre surface on screen, voxel indices (from, to); the serial changes with it.
  std::array<int, 6> fibreSeed{0, 0, 0, 0, 0, 0};
  unsigned fibreSeedSerial = 0; // a re-extraction is running; the previous mesh stays on screen

  render::FabricParams fabric;
  // The fabric only within fabricAlongMm of the tracts on screen (session::SetFabricAlong; `render
  // --fabric-along`), the grey beneath elsewhere (FA when no background is chosen). fabricAlongPending: its
  // proximity weight is being built.
  // The Profile panel (session::SetProfile, HoverProfileNode): the profile of the streamlines profiled
  // (ViewerScene::profileSource) along `scalar`, as `dtfabric profile` computes it, per node its mean and
  // confidence interval and the core's position; the node hovered and the node pinned (-1: none).
  struct Profile {
    bool on = false;
    std::string scalar = "fa";
    std::vector<std::string> scalars; // offered for the data on screen
    bool pending = false;
    std::string error, axis;
    std::size_t streamlines = 0;
    std::vector<double> mean, ciLow, ciHigh;
    std::vector<glm::dvec3> core;
    int hovered = -1, pinned = -1;
  } profile;
  bool fabricAlong = false;
  double fabricAlongMm = 2.0;
  bool fabricAlongPending = false;
  render::StandardView view = render::StandardView::Axial;
  bool neurological = false;
  bool split = false;
  bool linked = true;
  SecondPane secondPane = SecondPane::OtherColourMode;
  bool ortho = false;            // the ortho layout (ui::SetOrtho)
  glm::dvec3 crosshair{0.0};     // its crosshair, world RAS mm
  std::array<int, 3> orthoSlice{0, 0, 0}; // the slices through it: axial, coronal, sagittal indices
  bool recording = false;        // a turntable is being recorded (ui::RecordMovie)
  int recordedFrames = 0, recordFrames = 0;
  std::string recordStatus;      // the last recording: what it wrote, or why not
  std::string background;        // the grey beneath: a file, fa, md, "mean b=0", or "" (FA within the data)
  bool legend = true, scaleBar = true, colourBar = true; // figure furniture over the panes (SetFurniture)

  bool busy = false;      // loading / fitting on the worker thread
  std::string busyStage;  // e.g. "reading tensors"
  double busySeconds = 0; // time since the work started

  ProbeInfo probe;
  std::vector<std::string> errorChain; // non-empty: the error modal is open (outermost context first)
  std::string overwritePath; // non-empty: an output the user asked for exists; the prompt asks to replace it

  bool helpShown = false;  // the mouse and keyboard bindings over the scene (ShowHelp)
  double uiScale = 1;      // the panels', fonts' and furniture's scale on screen (SetUiScale)
  bool uiScaleAuto = true; // ... taken from the monitor (false: --ui-scale or the View panel)

  double frameMs = 0;
  bool converged = false; // the fabric reached still quality; rendering idles
  // Tracts (Tracts panel): the set on screen, loaded or tracked; analysis uses all its points.
  std::string tractPath; // file, or "tracked (...)"; empty: none
  bool tractsLoading = false;
  std::size_t tractCount = 0, tractPoints = 0;
  double tractMeanLengthMm = 0;
  bool tractsVisible = true;
  double tractsNearMm = 3.0; // 0: every tract
  double tractWidthPx = 2.0;
  double tractsClipMm = 0;       // camera-facing clip slab half-width (0: off), see SetTractsClip
  double tractsClipOffsetMm = 0; // its centre's distance beyond the surface centre along the view
  // Colouring and groups of the tracts on screen (SetTractColour, SetTractGroups).
  std::vector<std::string> tractDataNames;     // per-point, then per-streamline data of the loaded tracts
  std::vector<std::string> tractGroupNames;    // groups of the loaded tracts (.trx)
  std::vector<char> tractGroupShown;           // per tractGroupNames
  std::string tractColourBy;                   // data name; empty: DEC
  double tractColourLo = 0, tractColourHi = 1; // the range mapped to the colour map's ends
  bool tractsSelecting = false;                // the selection for the current surface is being computed
  bool tractsSlab = false; // planar surface: every tract, in a slab around its plane (half-width
                           // tractsClipMm, else tractsNearMm)
  std::size_t tractsShownLines = 0, tractsShownPoints = 0; // after selection and display decimation
  int tractsLevel = 0;            // level of detail on screen (0 = every display point)
  double tractsLevelFraction = 1; // share of that level's segments drawn
  // The ROI selection (Tracts panel's regions; ui/session/roi_selection.h).
  surfaces::RegionSet roiSet;   // the regions applied, in order (ends-only for the whole set)
  std::vector<char> roiVisible; // per region: its outline and shape are drawn
  bool roiHideOthers = true;    // the streamlines left out are hidden (else dimmed)
  bool roiActive = false;       // a region applies to the tracts on screen
  std::size_t roiSelected = 0;  // streamlines selected (every streamline when not active)
  bool roiSelecting = false;    // a selection (or the tracts' index) is being computed
  std::string roiStage;         // its stage, e.g. "indexing streamlines"
  double roiSelectMs = 0;       // the last selection's time on the worker
  std::string roiStatus;        // the last region file or selection save: what it wrote, or why not
  // Tracking on the worker thread.
  bool tracking = false;
  double trackProgress = 0; // 0..1 (seeds done / planned)
  std::size_t trackSeedsDone = 0;
  std::string trackStatus; // the last run: what it produced, or why not
  std::string saveStatus;
  // Agreement of the tracts near the surface with the fabric (surfaces/analyses/agreement.h).
  bool agreementRunning = false;
  bool hasAgreement = false;
  std::vector<float> agreementHistogram; // counts per bin of agreementBinDeg over 0..90 degrees
  double agreementBinDeg = 10, agreementMeanDeg = 0, agreementMedianDeg = 0, agreementFracBelow15 = 0;
  double agreementNearMm = 0;
  std::size_t agreementPoints = 0, agreementNearPoints = 0, agreementSkipped = 0;
  std::string agreementSurface; // the surface it was computed on
};

} // namespace dtf::session
