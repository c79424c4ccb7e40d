// What the viewer's user asked for. Panels (ui/panels.h), the key map (ui/keymap.h), mouse handling and
// viewer scripts all produce these values; only the app's viewer performs them. Keeping the requests as
// plain values lets the panels be tested without a window and lets every GUI action be replayed from a
// script (DESIGN.md section 5).
#pragma once

#include "render/camera.h"
#include "render/fabric_renderer.h"

#include <string>
#include <variant>
#include <vector>

namespace dtf::ui {

// The surface types of the Surface panel; Axial/Coronal/Sagittal are slices, Other is any other surface
// spec (iso=, plane=, mesh=) given in a script or on the command line.
enum class SurfaceKind { FaIsosurface, Axial, Coronal, Sagittal, Fibre, Other };

const char* surfaceKindName(SurfaceKind kind);
// Slice axis index 0 = axial, 1 = coronal, 2 = sagittal for a slice kind; -1 otherwise.
int sliceAxisOf(SurfaceKind kind);

// What the right pane of a split view shows.
enum class SecondPane { OtherColourMode, Phong };

struct LoadFile {
  std::string path;
  std::string layout = "auto"; // tensor layout override: auto|fsl|mrtrix|symmatrix|dtitk
};
struct SetSurfaceKind {
  SurfaceKind kind;
};
// `text` in the syntax of app/surface_spec.h (fa=T, slice=AXIS:I, fibre-voxel=..., mesh=FILE, ...).
struct SetSurfaceSpec {
  std::string text;
};
struct SetFaThreshold {
  double value;
};
struct SetSlice {
  int axis;  // 0 axial, 1 coronal, 2 sagittal
  int index; // voxel index along the axis, clamped by the viewer
};
struct SetFabricParams {
  render::FabricParams params;
};
struct SetView {
  render::StandardView view;
};
struct SetNeurological {
  bool on;
};
struct SetSplit {
  bool on;
};
struct SetLinkedCameras {
  bool on;
};
struct SetSecondPane {
  SecondPane mode;
};
struct ResetView {};
// Camera motion in window pixels (y down) over pane `pane` (-1 = the active pane).
struct Rotate {
  double dx, dy;
  int pane = -1;
};
struct Pan {
  double dx, dy;
  int pane = -1;
};
// Magnification: 2 shows everything twice as large.
struct Zoom {
  double factor;
  int pane = -1;
};
// A PNG of the whole window (panels included) or of the fabric panes only. Outputs never replace an input
// file; an existing file is replaced only with `force` (the GUI asks first, a script line says --force).
struct Screenshot {
  std::string path;
  bool sceneOnly = false;
  bool force = false;
};
struct SaveCamera {
  std::string path;
  bool force = false;
};
struct LoadCamera {
  std::string path;
};
// Streamlines (.tck, .trk, .vtk) to load and list; they are not drawn yet.
struct LoadTracts {
  std::string path;
};
struct DismissError {};
// The answer to the overwrite prompt (ViewerState::overwritePath): write the pending output or drop it.
struct ConfirmOverwrite {
  bool overwrite;
};
struct Quit {};

using Action =
    std::variant<LoadFile, SetSurfaceKind, SetSurfaceSpec, SetFaThreshold, SetSlice, SetFabricParams, SetView,
                 SetNeurological, SetSplit, SetLinkedCameras, SetSecondPane, ResetView, Rotate, Pan, Zoom,
                 Screenshot, SaveCamera, LoadCamera, LoadTracts, DismissError, ConfirmOverwrite, Quit>;

// Reused from frame to frame by the caller (clear(), keep the capacity), so idle frames do not allocate.
using ActionList = std::vector<Action>;

// A one-line description for logs and tests, e.g. "SetFaThreshold 0.3".
std::string describe(const Action& action);

} // namespace dtf::ui
