// SPDX-License-Identifier: GPL-3.0-or-later
// Saved sessions: a view script (app/viewer/view_script.h) that brings the viewer back to what is on screen,
// written as state, not as the history of what was done: the window size and UI scale, the data with its
// layout and paired tensor, the surface, every fabric option, the background, the furniture, the layout
// (split, linked, ortho, neurological), the crosshair, the tracts with their selection and colouring, and
// each pane's camera inline (`camera eye=... target=...`, no rotate or zoom). Paths are absolute. It starts
// with `session 1`, so `view --script FILE` checks every file it names before a window opens.
#pragma once

#include "app/viewer/viewer.h"

#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

// The script text for the scene in a window of width x height pixels; `uiScale` when one was chosen (none:
// the monitor's). What a script cannot bring back (tracts tracked in the viewer and not saved, an
// uncertainty map from the command line, the orientation check's correction) is named in `notes` and as a
// comment in the script.
std::string sessionScript(const ViewerScene& scene, int width, int height, std::optional<double> uiScale,
                          std::vector<std::string>* notes = nullptr);
// Writes `text` to `path` atomically (an existing file is the caller's to allow). Throws InputError.
void writeSessionFile(const std::string& path, const std::string& text);

} // namespace dtf::app
