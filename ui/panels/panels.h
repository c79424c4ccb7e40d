// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's Dear ImGui panels: Data, Surface, Fabric, Fibres (fibre sets), View and Tracts in a side bar,
// a status bar with the voxel under the cursor, a progress line for work on the worker thread, the error
// modal and the overwrite prompt. Each panel reads the ViewerState by const reference and appends what the
// user asked for to an ActionList; nothing is changed here (the session and the viewer perform the actions).
// Needs a current ImGui context inside NewFrame()/Render(); no renderer backend is needed, so the panels also
// run headless in tests.
#pragma once

#include "ui/panels/file_browser.h"
#include "ui/session/actions.h"
#include "ui/session/viewer_state.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace dtf::ui {

// Widget state that ImGui needs to own between frames (text fields), owned by the caller.
struct PanelBuffers {
  std::array<char, 1024> openPath{};
  int layout = 0;                      // index into kLayoutNames
  std::array<char, 1024> tensorPath{}; // fibre sets: the paired tensor of the next load
  std::array<char, 1024> screenshotPath{};
  std::array<char, 1024> cameraPath{};
  std::array<char, 1024> moviePath{}; // Record: .mp4, .gif or DIR/
  int movieFrames = 36;
  int movieKind = 0;                          // turntable, axial/coronal/sagittal sweep, FA sweep
  double movieFaLo = 0.15, movieFaHi = 0.5;   // FA sweep
  std::array<char, 1024> backgroundPath{}; // the grey beneath: FILE, fa or md
  std::array<char, 1024> tractPath{};
  std::array<char, 1024> tractSavePath{};
  // Regions of the ROI selection (Tracts panel).
  int roiPlace = 0;     // the next left click in a slice pane adds: 0 nothing, 1 a sphere, 2 a box
  int roiKind = 0;      // the kind of the regions added: include, exclude, include-ordered
  float roiSizeMm = 5;  // their radius (sphere) or half-size (box)
  int roiRenaming = -1; // the region whose name roiName edits (-1: none)
  std::array<char, 128> roiName{};
  std::array<char, 1024> roiPath{};         // a region set file to load or save
  std::array<char, 1024> roiSelectedPath{}; // where the selected streamlines are saved
  std::array<char, 128> roiGroup{};         // a .trx output: the selection as this group of every streamline
  session::TrackRequest track{[] {
    session::TrackRequest r;
    r.seeds = session::SeedKind::Surface; // the surface on screen
    return r;
  }()}; // the tracking request being edited
  double agreementNearMm = 2.0;      // `dtfabric compare --near`
  int agreementBins = 9;
  std::array<int, 3> fibreFrom{0, 0, 0}, fibreTo{0, 0, 0}; // fibre surface seed line, voxel indices
  unsigned fibreSeedSerial = 0; // ViewerState::fibreSeedSerial last copied into fibreFrom/To
  std::array<char, 1024> sessionPath{}; // Save session: a view script (.dtfview)
  float uiScaleEdit = 1;                 // the View panel's UI scale while its slider is held
  bool uiScaleDragging = false;
  bool profileHovering = false; // the mouse was over the profile's plot last frame
  FileBrowserState browser;             // the in-window file browser
  // Panel header -> open, as last drawn; set before the first frame to restore them (remembered settings).
  std::map<std::string, bool> panelsOpen;
  bool panelsRestored = false; // panelsOpen was applied to the headers
  // Tests set this to learn where widgets are: label -> rectangle centre (window pixels).
  std::map<std::string, std::array<float, 2>>* itemCentres = nullptr;
};

// Layout of the window: the side bar on the left, the status bar at the bottom, the scene in between. The
// sizes are window pixels at the UI scale (kSideWidth, kStatusHeight times the scale).
inline constexpr float kSideWidth = 300, kStatusHeight = 26;
// The panels' font size at scale 1, pixels; widget sizes are given for it and scale with the font (em()).
inline constexpr float kBaseFontPixels = 14;
struct PanelLayout {
  float sideWidth = kSideWidth;
  float statusHeight = kStatusHeight;
  void setScale(float scale) {
    sideWidth = kSideWidth * scale;
    statusHeight = kStatusHeight * scale;
  }
};
// A size given for scale 1 at the current font's scale.
float em(float pixelsAtScale1);

// Scene rectangle (window pixels, y down) left free by the panels for a window of the given size.
void sceneRect(const PanelLayout& layout, float width, float height, float rect[4]);

void dataPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
void surfacePanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
void fabricPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
// Shown for a fibre set: its file, layout and FA source, the fibre threshold, the populations drawn.
void fibresPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
void viewPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
void tractsPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
void statusBar(const session::ViewerState& state, const PanelLayout& layout);
void errorModal(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
// Asks whether to replace the existing file state.overwritePath (a screenshot, camera or tract file the
// user asked for): ConfirmOverwrite{true} or {false}.
void overwriteModal(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);

// The mouse and keyboard bindings (ui/session/keymap.h) over the scene, when state.helpShown.
void helpOverlay(const session::ViewerState& state, const PanelLayout& layout, session::ActionList& out);
// The in-window file browser when open (ui/panels/file_browser.h).
void fileBrowserPanel(const session::ViewerState& state, PanelBuffers& buffers, session::ActionList& out);
// In the open browser, does what a double click on the entry `name` does: enters a folder ("..": the parent),
// chooses a file; for an output a new name is chosen in the folder shown. False (with the reason shown in
// the browser) when there is no such entry or the browser is closed.
bool pickInBrowser(PanelBuffers& buffers, const std::string& name, session::ActionList& out);
// The panels' open path for a path chosen in a dialog (the desktop's or the browser): it goes into the
// target's field and, for an input, appends what the panel's button appends for a typed path (LoadFile with
// the Data panel's layout and tensor, LoadTracts, SetBackground, a mesh=PATH surface); an output's path is
// put in its field (Save session also saves).
void choosePath(PanelBuffers& buffers, session::FileTarget target, const std::string& path,
                session::ActionList& out);
// Records the last widget's centre under `label` for tests (PanelBuffers::itemCentres).
void probeItem(PanelBuffers& buffers, const char* label);

// All of the above for one frame.
void drawPanels(const session::ViewerState& state, PanelBuffers& buffers, const PanelLayout& layout,
                session::ActionList& out);

// Layout names in the order of PanelBuffers::layout.
extern const std::array<const char*, 8> kLayoutNames;

} // namespace dtf::ui
