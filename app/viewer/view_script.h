// Viewer scripts (`dtfabric view --script FILE`): one command per line, replayed by the viewer as if the
// user had done it, so every figure can be reproduced. Parsing is pure (text in, steps out) and checks
// everything it can before a window opens; a bad line is a UsageError "FILE:LINE: ...".
//
//   load PATH                 open a tensor volume (or DWI with sibling .bval/.bvec)
//   surface SPEC              any surface of app/scene/surface_spec.h (fa=0.3, slice=axial:20, fibre-voxel=...)
//   fa T                      FA isosurface at T (0 < T < 1)
//   slice AXIS INDEX          axial|coronal|sagittal slice INDEX
//   key NAME                  Up, Down, PgUp, PgDn, A, C, S, R
//   rotate DX DY              trackball drag by DX, DY window pixels (y down)
//   pan DX DY                 pan by DX, DY pixels
//   zoom F                    magnify by F (2 = twice as large)
//   view NAME                 superior|inferior|anterior|posterior|left|right|axial|coronal|sagittal
//   split on|off              two panes (linked on|off: one camera); split colour|phong|tracts also picks the
//                             right pane: the other colour mode, Phong shading, or fabric + tracts (the left
//                             pane then shows the fabric alone)
//   linked on|off, neurological on|off
//   set PARAM VALUE           fabric parameter: lod k iterations epsilon r colour(medical|engineering)
//                             lighting(on|off) silhouette(on|off) sharpen depth-colour contrast step fade
//   wait FRAMES               render FRAMES more frames
//   screenshot [--force] PATH        PNG of the whole window, panels included
//   screenshot-scene [--force] PATH  PNG of the fabric panes only (no panels, no labels)
//   camera-save [--force] PATH, camera-load PATH
//                             outputs never replace an input; an existing file only with --force (or
//                             `view --force` for the whole script)
//   probe X Y                 print the status bar's voxel under scene pixel (X, Y) (y down) to stderr
//   resize WxH                resize the window (e.g. 800x600)
//   tracts PATH               load .tck/.trk/.vtk streamlines and draw them over the fabric
//   tracts-visible on|off     show or hide the tracts
//   tracts-near MM            only tract segments within MM of the surface (a slab on planar surfaces);
//                             0 = every tract (default 3)
//   tracts-clip MM [DEPTH]    draw only tract points within MM of the plane facing the camera through the
//                             surface's centre, moved DEPTH mm away from the viewer (default 0); 0 = off;
//                             on a planar surface, within MM of its plane
//   tract-width PX            tube width in pixels (default 2)
//   track [KEY=VALUE ...]     deterministic tracking on the worker (replaces the tracts on screen):
//                             from=surface|slice:AXIS[:I]|sphere:X,Y,Z,R|fa:T (default surface),
//                             select=N|seeds=N|per-voxel=K (default select=1000; per-voxel with from=fa),
//                             fa-stop=F angle=DEG step=MM min-length=MM max-length=MM seed=S rk4|euler
//   track-cancel              cancel a running `track` (runs without waiting for it)
//   tracts-save PATH [force]  write the tracts (all points) to .tck/.trk/.vtk; an existing file only with
//   force agreement [MM [BINS]]     tract/fabric angles within MM (default 2) of the surface, BINS bins
//   (default 9):
//                             the numbers of `dtfabric compare`, printed to stderr
//   quit                      close the viewer
// `#` starts a comment; blank lines are skipped.
#pragma once

#include "render/fabric_renderer.h"
#include "ui/actions.h"
#include "ui/keymap.h"

#include <string>
#include <variant>
#include <vector>

namespace dtf::app {

struct ScriptWait {
  int frames;
};
struct ScriptProbe {
  double x, y; // scene pixels, y down
};
struct ScriptResize {
  int width, height; // window pixels
};
struct ScriptSetParam {
  std::string name; // canonical name from the list above
  double value;     // on/off -> 1/0, medical/engineering -> 0/1
};

struct ScriptStep {
  int line = 0; // 1-based line in the file
  std::variant<ui::Action, ui::Key, ScriptWait, ScriptSetParam, ScriptProbe, ScriptResize> command;
};

struct ViewScript {
  std::string file;
  std::vector<ScriptStep> steps;
};

// Parses script text; `file` names it in messages. Throws UsageError "FILE:LINE: what is wrong".
ViewScript parseViewScript(const std::string& text, const std::string& file);
// Reads and parses a script file. Throws InputError when it cannot be read, UsageError for a bad line.
ViewScript loadViewScript(const std::string& path);
// Checks the outputs of screenshot/camera-save lines before a window opens: a path naming one of `inputs`,
// the script itself or a file the script reads (load with its .bval/.bvec, tracts, surface files) is
// refused whatever --force says; an existing file is refused unless its line or `force` says --force.
// Throws InputError "FILE:LINE: ...". The viewer checks again when it writes (files may appear meanwhile).
void checkScriptOutputs(const ViewScript& script, std::vector<std::string> inputs, bool force);
// Applies a `set` line to fabric parameters (values already validated by the parser).
void applyScriptParam(render::FabricParams& params, const ScriptSetParam& param);

} // namespace dtf::app
