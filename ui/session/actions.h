// SPDX-License-Identifier: GPL-3.0-or-later
// What the viewer's user asked for. Panels (ui/panels.h), the key map (ui/keymap.h), mouse handling and
// viewer scripts all produce these values; the session (ui/session/viewer_session.h) and the viewer's panes
// perform them. Plain values, below ui/ (namespace ui: the vocabulary of the panels), so the panels can be
// tested without a window, every GUI action can be replayed from a script, and the session needs no ImGui.
#pragma once

#include "render/camera.h"
#include "render/fabric_params.h"
#include "surfaces/selection/regions.h"
#include "ui/session/track_request.h"

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace dtf::session {

// The surface types of the Surface panel; Axial/Coronal/Sagittal are slices, Other is any other surface
// spec (iso=, plane=, mesh=) given in a script or on the command line.
enum class SurfaceKind { FaIsosurface, Axial, Coronal, Sagittal, Fibre, Other };

const char* surfaceKindName(SurfaceKind kind);
// Slice axis index 0 = axial, 1 = coronal, 2 = sagittal for a slice kind; -1 otherwise.
int sliceAxisOf(SurfaceKind kind);

// What the right pane of a split view shows: the other colour mode, Phong shading, or the same fabric with
// the tracts (the left pane then shows the fabric alone).
enum class SecondPane { OtherColourMode, Phong, Tracts };
// "colour", "phong", "tracts" (the script's names).
const char* secondPaneName(SecondPane mode);

// A tensor volume, a DWI, or a fibre set (peaks, bedpostx, ...: io/formats/fibre_io.h) as `dtfabric render` reads it.
struct LoadFile {
  std::string path;
  std::string layout = "auto"; // auto, a tensor layout (fsl|mrtrix|symmatrix|dtitk) or a fibre layout
  std::string tensor;          // fibre sets: a tensor volume on the same grid (FA); empty: none
};
struct SetSurfaceKind {
  SurfaceKind kind;
};
// `text` in the syntax of ui/session/surface_spec.h (fa=T, slice=AXIS:I, fibre-voxel=..., mesh=FILE, ...).
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
  std::optional<SecondPane> mode = std::nullopt; // also sets what the right pane shows
};
struct SetLinkedCameras {
  bool on;
};
struct SetSecondPane {
  SecondPane mode;
};
// The ortho layout: axial, coronal and sagittal slices through the crosshair (three panes) beside the 3D
// pane; off: the single (or split) 3D view.
struct SetOrtho {
  bool on;
};
// Moves the crosshair of the ortho layout to a world RAS point (mm; clamped to the data); the slice panes
// follow to the slices through it.
struct SetCrosshair {
  glm::dvec3 world;
};
// Records what the 3D pane shows (its surface, fabric and camera): a turntable (a full turn about the pane's
// vertical, the screen's up direction through the camera's target), a slice sweep or an FA-threshold sweep,
// to an MP4, a GIF or a directory of PNG frames (io/formats/movie_writer.h),
// the advection state carried from frame to frame. An existing output only with `force`; never an input.
// Sweep: the pane's camera held while the slice moves through the slices holding data along `axis`;
// FaSweep: the FA isosurface from faLo to faHi (the surface re-extracted per frame).
struct RecordMovie {
  std::string path;
  int frames = 36;
  double fps = 12;
  bool force = false;
  enum class Kind { Turntable, Sweep, FaSweep } kind = Kind::Turntable;
  std::string axis = "axial";     // Sweep
  double faLo = 0.15, faHi = 0.5; // FaSweep
};
// The grey beneath the fabric: a scalar volume FILE on any grid (resampled in world space), fa or md of the
// data, or none (FA within the data); empty: the default (a DWI's mean b=0 image in the anatomy look).
// `window`: LO,HI, or empty (a FILE's 1st..99th percentile).
struct SetBackground {
  std::string what;
  std::string window;
};
// The fabric only near the tracts on screen (`render --fabric-along`): on/off and the distance in mm (in
// (0, 1000]), each when given.
struct SetFabricAlong {
  std::optional<bool> on;
  std::optional<double> mm;
};
// The Profile panel: profile the streamlines (on), along which scalar (fa, md, ad, rd), each when given.
struct SetProfile {
  std::optional<bool> on;
  std::optional<std::string> scalar;
};
// A node of the profile hovered (-1: none): the crosshair goes to its core position; `pin` pins it (again:
// unpins), so the crosshair returns there when no node is hovered.
struct HoverProfileNode {
  int node = -1;
  bool pin = false;
};
// The figure furniture drawn over the panes as `dtfabric render` draws it: each piece that is given.
struct SetFurniture {
  std::optional<bool> legend, scaleBar, colourBar;
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
// Streamlines (.tck, .trk, .vtk, world RAS mm) to load and draw over the fabric.
struct LoadTracts {
  std::string path;
};
struct SetTractsVisible {
  bool on;
};
// Only tract segments within `mm` of the surface are shown (a slab of half-width `mm` around a planar
// surface); 0 shows every tract.
struct SetTractsNear {
  double mm;
};
struct SetTractWidth {
  double px;
};
// A clip slab for large tractograms: only tract points within `mm` of the plane facing the camera through
// the surface's centre, moved `offsetMm` along the view direction (away from the viewer), are drawn. It
// follows the camera; 0 turns it off. On a planar surface with a near-surface distance, that slab applies.
struct SetTractsClip {
  double mm;
  double offsetMm = 0;
};
// Colours the tracts by a per-point or per-streamline data value through the tract colour map
// (render/tract_renderer.h) over `range` (default: the value's min..max); an empty `value` restores DEC.
struct SetTractColour {
  std::string value;
  std::optional<std::pair<double, double>> range;
};
// Shows only the streamlines of the named groups (e.g. a bundle of an AFQ .trx); `all` shows every
// streamline, grouped or not. No group and not `all` hides every streamline.
struct SetTractGroups {
  std::vector<std::string> shown;
  bool all = true;
};
// Deterministic tensor tractography from the viewer (the options of `dtfabric track`; track_request.h).
struct TrackTracts {
  TrackRequest request;
};
struct CancelTracking {};
// Writes the tracts on screen (all points, not the display decimation) to .tck/.trk/.vtk, atomically. An
// existing file is replaced only with `overwrite`; otherwise the panel asks first (`askFirst`) and a
// script fails.
// Writes the tracts on screen (.tck, .trk, .vtk); an existing file is replaced only with `force` (the
// overwrite prompt sets it), an input never.
// `selected`: only the streamlines the ROI selection keeps (every value and group kept, as `dtfabric select`
// writes them); with `asGroup` (a .trx output) every streamline, the selection added as that group.
struct SaveTracts {
  std::string path;
  bool force = false;
  bool selected = false;
  std::string asGroup;
};
// The region set of the ROI selection (ui/session/roi_selection.h): the Tracts panel's regions and the
// script's roi lines. A region is added from its SPEC (ui/session/region_spec.h; a mask image is read then)
// or as given (`spec` empty).
struct RoiAdd {
  surfaces::RegionKind kind = surfaces::RegionKind::Include;
  std::string spec;
  surfaces::Region region;
};
// Replaces region `index` (moved, resized, renamed, another kind).
struct RoiSet {
  std::size_t index = 0;
  surfaces::Region region;
};
// Shows or hides region `index`'s outline and shape (it applies either way).
struct RoiVisible {
  std::size_t index = 0;
  bool on = true;
};
struct RoiRemove {
  std::size_t index = 0;
};
struct RoiClear {};
// Tests includes and excludes on the two end points only, for the whole set (`select --ends-only`).
struct RoiEndsOnly {
  bool on = false;
};
// The streamlines the selection leaves out are hidden (true) or drawn dimmed in grey (false).
struct RoiHideOthers {
  bool on = true;
};
// Writes the region set (the `select --roi` JSON, ui/session/region_spec.h), atomically; an existing file
// only with `force`, an input never.
struct SaveRegions {
  std::string path;
  bool force = false;
};
// Replaces the region set by a region set file's.
struct LoadRegions {
  std::string path;
};
// Angle between the tracts near the surface and the fabric's direction (surfaces/analyses/agreement.h, all points).
struct ComputeAgreement {
  double nearMm = 2.0;
  int bins = 9;
};
// What a file dialog picks a path for (ui/session/file_kinds.h): the panels' inputs and outputs.
enum class FileTarget {
  // inputs
  Data,
  Tensor,
  Background,
  Tracts,
  Mesh,
  Regions,
  Session,
  // outputs
  Screenshot,
  Camera,
  Movie,
  TractsSave,
  SessionSave,
  RegionsSave,
  SelectedSave
};
// Opens a file dialog for `target`: the desktop's own (the XDG desktop portal) where one runs, else the
// in-window browser, starting in `folder` (empty: the last folder). The chosen path goes where a typed one
// goes (ui/panels/panels.h choosePath).
struct Browse {
  FileTarget target;
  std::string folder;
};
// Sets pane `pane`'s camera (-1: the active pane; both when linked) as it is: a session's camera.
struct SetCamera {
  render::Camera camera;
  int pane = -1;
};
// Writes a view script that brings the viewer back to what is on screen (app/viewer/session_file.h).
struct SaveSession {
  std::string path;
  bool force = false;
};
// The mouse and keyboard bindings over the scene (F1 or ?): shown, hidden, or toggled (nullopt).
struct ShowHelp {
  std::optional<bool> on;
};
// The panels', fonts' and furniture's scale; 0: the monitor's content scale.
struct SetUiScale {
  double scale;
};
struct DismissError {};
// The answer to the overwrite prompt (ViewerState::overwritePath): write the pending output or drop it.
struct ConfirmOverwrite {
  bool overwrite;
};
struct Quit {};

using Action =
    std::variant<LoadFile, SetSurfaceKind, SetSurfaceSpec, SetFaThreshold, SetSlice, SetFabricParams, SetView,
                 SetNeurological, SetSplit, SetLinkedCameras, SetSecondPane, SetOrtho, SetCrosshair,
                 RecordMovie, SetBackground, SetFabricAlong, SetProfile, HoverProfileNode, SetFurniture,
                 ResetView, Rotate, Pan, Zoom, Screenshot, SaveCamera, LoadCamera, LoadTracts,
                 SetTractsVisible, SetTractsNear, SetTractWidth, SetTractsClip, SetTractColour,
                 SetTractGroups, TrackTracts, CancelTracking, SaveTracts, RoiAdd, RoiSet, RoiVisible,
                 RoiRemove, RoiClear, RoiEndsOnly, RoiHideOthers, SaveRegions, LoadRegions, ComputeAgreement,
                 Browse, SetCamera, SaveSession, ShowHelp, SetUiScale, DismissError, ConfirmOverwrite, Quit>;

// Reused from frame to frame by the caller (clear(), keep the capacity), so idle frames do not allocate.
using ActionList = std::vector<Action>;

// Splits an error message chain "while A: while B: cause" into its links, outermost first (the error modal).
std::vector<std::string> splitErrorChain(const std::string& message);

// A one-line description for logs and tests, e.g. "SetFaThreshold 0.3".
std::string describe(const Action& action);

} // namespace dtf::session
