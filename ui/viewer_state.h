// The viewer's state as the panels see it: a plain snapshot the app's viewer keeps up to date and hands to
// ui/panels.h by const reference each frame. Strings here change only when the data or the surface
// change, so drawing the panels from it does not allocate.
#pragma once

#include "render/camera.h"
#include "render/fabric_renderer.h"
#include "ui/actions.h"

#include <array>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace dtf::ui {

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

// The voxel under the mouse cursor (status bar).
struct ProbeInfo {
  bool onSurface = false; // the cursor is over the rendered surface
  bool inData = false;    // ... and inside the tensor grid with a valid tensor
  glm::dvec3 world{0.0};  // world RAS mm
  glm::ivec3 voxel{0};    // nearest voxel index
  double fa = 0;
  glm::dvec3 eigenvalues{0.0}; // mm^2/s, descending
  glm::dvec3 e1{0.0};          // principal direction, world RAS
};

struct ViewerState {
  bool hasData = false;
  DataInfo data;
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
  render::StandardView view = render::StandardView::Axial;
  bool neurological = false;
  bool split = false;
  bool linked = true;
  SecondPane secondPane = SecondPane::OtherColourMode;

  bool busy = false;      // loading / fitting on the worker thread
  std::string busyStage;  // e.g. "reading tensors"
  double busySeconds = 0; // time since the work started

  ProbeInfo probe;
  std::vector<std::string> errorChain; // non-empty: the error modal is open (outermost context first)
  std::string overwritePath; // non-empty: an output the user asked for exists; the prompt asks to replace it

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
  double tractsClipMm = 0;       // camera-facing clip slab half-width (0: off), see ui::SetTractsClip
  double tractsClipOffsetMm = 0; // its centre's distance beyond the surface centre along the view
  // Colouring and groups of the tracts on screen (ui::SetTractColour, ui::SetTractGroups).
  std::vector<std::string> tractDataNames;     // per-point, then per-streamline data of the loaded tracts
  std::vector<std::string> tractGroupNames;    // groups of the loaded tracts (.trx)
  std::vector<char> tractGroupShown;           // per tractGroupNames
  std::string tractColourBy;                   // data name; empty: DEC
  double tractColourLo = 0, tractColourHi = 1; // the range mapped to the colour map's ends
  bool tractsSelecting = false; // the selection for the current surface is being computed
  bool tractsSlab = false;      // planar surface: every tract, in a slab around its plane (half-width tractsClipMm, else tractsNearMm)
  std::size_t tractsShownLines = 0, tractsShownPoints = 0; // after selection and display decimation
  int tractsLevel = 0;            // level of detail on screen (0 = every display point)
  double tractsLevelFraction = 1; // share of that level's segments drawn
  // Tracking on the worker thread.
  bool tracking = false;
  double trackProgress = 0; // 0..1 (seeds done / planned)
  std::size_t trackSeedsDone = 0;
  std::string trackStatus; // the last run: what it produced, or why not
  std::string saveStatus;
  // Agreement of the tracts near the surface with the fabric (surfaces/agreement.h).
  bool agreementRunning = false;
  bool hasAgreement = false;
  std::vector<float> agreementHistogram; // counts per bin of agreementBinDeg over 0..90 degrees
  double agreementBinDeg = 10, agreementMeanDeg = 0, agreementMedianDeg = 0, agreementFracBelow15 = 0;
  double agreementNearMm = 0;
  std::size_t agreementPoints = 0, agreementNearPoints = 0, agreementSkipped = 0;
  std::string agreementSurface; // the surface it was computed on
};

} // namespace dtf::ui
