// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check's banner in the viewer: after a DWI or tensor file is loaded the check runs on the
// worker (surfaces/analyses/orientation_check.h); this panel warns when it is not ok: a two-line coloured strip across
// the top of the scene with the verdict (the reason as a tooltip), the contact sheet and, when another table
// scores best, "apply the correction" (in memory; saving a corrected table is explicit, with `dtfabric check
// --fix-bvec`). An ok verdict or a running check shows nothing. Like ui/panels.h it reads
// its state by const reference and returns what the user asked for; it changes nothing itself.
#pragma once

#include <array>
#include <map>
#include <string>

namespace dtf::ui {

struct OrientationBannerState {
  bool visible = false;      // a result (or a running check) to show
  bool running = false;      // the check is running on the worker
  std::string verdict;       // "ok", "corrected" or "inconclusive"
  std::string reason;        // the check's one-line reason
  std::string correction;    // the best table's transform name, e.g. "-x y z" (corrected)
  bool applied = false;      // the correction is applied to the data in memory
  bool sheetShown = false;   // the contact sheet window is open
  unsigned sheetTexture = 0; // GL texture of the contact sheet (0: not rendered yet)
  int sheetWidth = 0, sheetHeight = 0;
};

enum class OrientationAction { None, ShowSheet, HideSheet, ApplyCorrection, Dismiss };

// Draws the banner at the top of the scene rectangle `rect` (x, y, w, h, window pixels) and, when
// sheetShown, the contact sheet window. Needs a current ImGui context inside a frame. `centres`, when set,
// receives each button's centre by label (window pixels, for tests).
OrientationAction orientationBanner(const OrientationBannerState& state, const float rect[4],
                                    std::map<std::string, std::array<float, 2>>* centres = nullptr);

// Banner colour by verdict: green ok, red corrected, amber inconclusive (RGB in [0, 1]).
void orientationBannerColour(const std::string& verdict, float rgb[3]);

} // namespace dtf::ui
