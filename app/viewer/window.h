// SPDX-License-Identifier: GPL-3.0-or-later
// The desktop viewer: a GLFW window with ImGui panels over the scene of app/viewer/viewer.h.
#pragma once

#include "app/viewer/view_script.h"
#include "io/model/volume.h"
#include "ui/session/actions.h"
#include "ui/session/fibre_input.h"
#include "ui/session/render_job.h"

#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

struct ViewerWindowOptions {
  std::vector<std::string> inputs;    // the first is loaded, all are listed under recent files
  std::string surface;                // first surface (ui/session/surface_spec.h syntax); empty: FA 0.25
  std::string layout = "auto";        // tensor or fibre layout of the first input
  std::string tensor;                 // a fibre-set first input: its paired tensor volume (FA)
  int width = 1280, height = 800;     // window size, pixels
  bool ortho = false;                 // open in the ortho layout
  const ViewScript* script = nullptr; // replayed when given (outputs already checked)
  std::optional<session::UncertaintyMap> uncertainty; // a cone map that frays the threads; read by the caller
  session::SetBackground background;                  // --background, --background-window
  session::SetFurniture furniture;                    // --no-legend, --no-scale-bar, --no-colour-bar
  session::FabricAlong fabricAlong;                   // --fabric-along: its tracts loaded, the switch on
  bool sizeGiven = false;                             // --size (wins over the remembered size)
  std::optional<double> uiScale;                      // --ui-scale; none: remembered, else the monitor's
  // The remembered settings (ui/session/viewer_config.h): read at the start and written at the end when
  // set; runs with a script and --no-config leave it empty.
  std::string configPath;
};

// Opens the window and runs until it closes or the script quits; returns the exit code. Throws GlError when
// no window or GL 4.5 context can be had.
int runViewerWindow(const ViewerWindowOptions& options);

} // namespace dtf::app
