// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view`: checks the arguments and the script before a window opens, then runs the viewer.
#include "app/cli/commands.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "app/viewer/view_script.h"
#include "app/viewer/window.h"
#include "io/diffusion/uncertainty.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "ui/session/fibre_input.h"
#include "ui/session/render_job.h"
#include "ui/session/surface_spec.h"
#include "ui/session/viewer_config.h"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace dtf::app {

namespace {

const char* kIntro =
    "Opens the viewer: the fabric on a surface of the first INPUT (tensor volume, a DWI with sibling\n"
    ".bval/.bvec, or a fibre set as `dtfabric render` reads it: MRtrix or DIPY peaks, FSL bedpostx, ...),\n"
    "with Data, Surface, Fabric, Fibres (fibre sets: threshold, populations drawn), View and Tracts\n"
    "panels (load or track streamlines, draw them over the fabric near the surface, save them, and\n"
    "measure their agreement with the fabric). Further INPUTs are listed under recent files.\n"
    "\n"
    "Mouse: left-drag rotate, middle-drag or shift-left-drag pan, wheel zoom. Files dropped on the window\n"
    "open by kind (a volume as data, a tractogram as tracts, a mesh as the surface); each path field has a\n"
    "file dialog (the desktop's through the XDG portal, else the viewer's own).\n"
    "Keys: Up/Down and PgUp/PgDn step the slice, A/C/S axial/coronal/sagittal slice, R reset the view,\n"
    "F1 or ? the bindings over the scene. Save session (View panel) writes a script that `--script` replays.";

const char* kOutputs =
    "Screenshots, camera and tract files are written atomically. An input file is never replaced; in the\n"
    "window an existing file is replaced only after the overwrite prompt says so.\n"
    "\n"
    "Script commands\n";

} // namespace

const OptionTable& viewOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const ViewerWindowOptions d; // the defaults
    OptionTable t;
    t.command = "view";
    t.positionals = "[INPUT ...]";
    t.maxPositionals = OptionTable::kAnyNumber;
    t.intro = kIntro;
    t.options = {
        O::text("surface", "SPEC",
                "first surface: fa=T | slice=AXIS[:I] | plane=... | fibre=... | iso=FILE:V | mesh=FILE")
            .defaultSays("the FA 0.25 isosurface")
            .hidden(),
        layoutOption(LayoutNames::TensorOrFibre).hidden(),
        pairedTensorOption("FA (fa= surfaces, the split's tensor colours beside the fibres)"),
        O::text("size", "WxH", "window size in pixels, 320x240 to 8192x8192",
                std::to_string(d.width) + "x" + std::to_string(d.height))
            .checkedBy(checkSize)
            .hidden(),
        O::text(
            "uncertainty", "CONE",
            "a 95 % cone-of-uncertainty map in degrees (fit --bootstrap N --cone CONE) or a bedpostx folder "
            "with samples: the threads fray as the cone widens (Fabric panel: fray)"),
        O::text(
            "background", "FILE|fa|md",
            "the grey beneath the fabric: a scalar volume on any grid (a T1, say; resampled in world space), "
            "or the data's FA or MD (default: a DWI's mean b=0 image; View panel: background)"),
        O::text("fabric-along", "TRACTS[:MM]",
                "load TRACTS and draw the fabric only within MM (default 2) mm of them, the grey beneath "
                "elsewhere (FA when no background is chosen; Fabric panel: along the tracts)"),
        O::text("background-window", "LO,HI",
                "the background's grey ramp (default: a FILE's 1st..99th percentile)")
            .hidden(),
        O::flag("no-legend", "no orientation legend over the panes (View panel: legend)").hidden(),
        O::flag("no-scale-bar", "no scale bar over the panes (View panel: scale bar)").hidden(),
        O::flag("no-colour-bar", "no colour bar of the tract value (View panel: colour bar)").hidden(),
        O::number("ui-scale", "F", 0, Range::closed(0, 4),
                  "the panels', fonts' and furniture's scale, 0.5 to 4 (default 0: the monitor's content "
                  "scale; View panel: UI scale)")
            .hidden(),
        O::flag("no-config",
                "start with the default settings: the window size, panels and last folder remembered in "
                "$XDG_CONFIG_HOME/dtfabric (default ~/.config) are neither read nor written")
            .hidden(),
        O::flag("ortho",
                "open in the ortho layout: axial, coronal and sagittal slices through a crosshair (click a "
                "slice pane to move it) beside the 3D pane"),
        O::text("script", "FILE",
                "replay a viewer script: one command of the list below per line, `#` comments.\n"
                "A bad line fails before the window opens (exit code 2); with `quit`, the exit code is 2 "
                "when any step failed (3 when the failure was GL's: context, texture limits, GPU memory)."),
        O::flag(
            "force",
            "let the script's screenshot, camera-save and tracts-save lines replace existing files (never an "
            "input); without it such a line fails, unless it says `screenshot --force PATH`"),
    };
    t.epilogue = kOutputs + scriptCommandsHelp();
    return t;
  }();
  return table;
}

int cmdView(const CommandArgs& argv) {
  ParsedOptions args(viewOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::vector<std::string> inputs = args.positionals();
  const auto scriptPath = args.get("script");
  ViewerWindowOptions o;
  parseSize(args.text("size"), o.width, o.height, 320, 240);
  const std::string surface = args.text("surface");
  const std::string layout = args.text("layout");
  const std::string tensor = args.text("tensor");
  const bool force = args.flag("force");
  const std::string uncertainty = args.text("uncertainty");
  o.ortho = args.flag("ortho");
  o.sizeGiven = args.given("size");
  const double uiScale = args.number("ui-scale");
  if (uiScale != 0 && !(uiScale >= 0.5 && uiScale <= 4))
    throw UsageError("--ui-scale must lie in [0.5, 4] (or 0: the monitor's)");
  if (uiScale != 0) o.uiScale = uiScale;
  const bool noConfig = args.flag("no-config");
  o.background = {args.text("background"), args.text("background-window")};
  o.furniture = {!args.flag("no-legend"), !args.flag("no-scale-bar"), !args.flag("no-colour-bar")};
  if (auto along = args.get("fabric-along")) {
    o.fabricAlong = session::parseFabricAlong(*along);
    if (!std::filesystem::is_regular_file(o.fabricAlong.path)) // exit code 2 before a window opens
      throw InputError("--fabric-along " + *along + ": no tract file " + o.fabricAlong.path);
  }
  args.finish();
  if (!o.background.window.empty() && o.background.what.empty())
    throw UsageError("--background-window needs --background");
  if (!o.background.what.empty() && o.background.what != "fa" && o.background.what != "md")
    io::readHeader(o.background.what); // an unreadable file is exit code 2 before a window opens
  if (!surface.empty()) session::parseSurfaceSpec(surface); // usage errors before a window opens
  if (!io::isFibreLayoutName(layout)) io::parseLayout(layout);
  if (!tensor.empty() && inputs.empty()) throw UsageError("--tensor pairs a tensor with a fibre-set INPUT");

  std::optional<ViewScript> script;
  if (scriptPath) {
    try {
      script = loadViewScript(*scriptPath);
    } catch (const UsageError& e) {
      throw InputError(e.what()); // a bad script is bad input (exit code 2), not bad usage
    }
    checkScriptOutputs(*script, inputs, force);
    checkSessionInputs(*script); // a session naming a missing file: exit code 2, no window
    if (force)
      for (ScriptStep& step : script->steps)
        if (auto* a = std::get_if<session::Action>(&step.command)) {
          if (auto* shot = std::get_if<session::Screenshot>(a)) shot->force = true;
          if (auto* camera = std::get_if<session::SaveCamera>(a)) camera->force = true;
          if (auto* movie = std::get_if<session::RecordMovie>(a)) movie->force = true;
        }
  }

  if (!uncertainty.empty()) { // read before a window opens: a bad map is exit code 2
    try {
      o.uncertainty = session::readUncertainty(uncertainty);
    } catch (...) {
      rethrowWithContext("while reading the uncertainty map " + uncertainty);
    }
  }
  o.inputs = inputs;
  o.surface = surface;
  o.layout = layout;
  o.tensor = tensor;
  o.script = script ? &*script : nullptr;
  // Runs with a script neither read nor write the remembered settings (they must replay the same anywhere).
  if (!script && !noConfig) o.configPath = session::viewerConfigPath();
  return runViewerWindow(o);
}

} // namespace dtf::app
