// `dtfabric view`: checks the arguments and the script before a window opens, then runs the viewer.
#include "app/cli/args.h"
#include "app/cli/commands.h"
#include "app/scene/surface_spec.h"
#include "app/viewer/view_script.h"
#include "app/viewer/window.h"
#include "io/fibre_io.h"
#include "io/model/error.h"
#include "io/tensor_io.h"

#include <cstdio>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace dtf::app {

namespace {

const char* kHelp = R"(usage: dtfabric view [INPUT ...] [OPTIONS]

Opens the viewer: the fabric on a surface of the first INPUT (tensor volume, a DWI with sibling
.bval/.bvec, or a fibre set as `dtfabric render` reads it: MRtrix or DIPY peaks, FSL bedpostx, ...), with
Data, Surface, Fabric, Fibres (fibre sets: threshold, populations drawn), View and Tracts panels (load or track streamlines, draw them over
the fabric near the surface, save them, and measure their agreement with the fabric). Further INPUTs are
listed under recent files.

Mouse: left-drag rotate, middle-drag or shift-left-drag pan, wheel zoom.
Keys: Up/Down and PgUp/PgDn step the slice, A/C/S axial/coronal/sagittal slice, R reset the view.

Options
  --surface SPEC   first surface: fa=T | slice=AXIS[:I] | plane=... | fibre=... | iso=FILE:V | mesh=FILE
  --layout L       tensor layout override (fsl, mrtrix, symmatrix, dtitk) or fibre layout (mrtrix-peaks,
                   dipy-peaks, bedpostx)
  --tensor F       fibre sets: a tensor volume on the same grid for FA (fa= surfaces, the split's tensor
                   colours beside the fibres)
  --size WxH       window size in pixels (default 1280x800)
  --script FILE    replay a viewer script: one command of the list below per line, `#` comments.
                   A bad line fails before the window opens (exit code 2); with `quit`, the exit code is 2
                   when any step failed (3 when the failure was GL's: context, texture limits, GPU memory).
  --force          let the script's screenshot, camera-save and tracts-save lines replace existing files
                   (never an input); without it such a line fails, unless it says `screenshot --force PATH`

Screenshots, camera and tract files are written atomically. An input file is never replaced; in the window an
existing file is replaced only after the overwrite prompt says so.

Script commands
)";

} // namespace

int cmdView(const CommandArgs& argv) {
  Args args(argv, {"help", "force"});
  if (args.flag("help")) {
    std::fputs(kHelp, stdout);
    std::fputs(scriptCommandsHelp().c_str(), stdout);
    return 0;
  }
  const std::vector<std::string> inputs = args.positionals();
  const auto scriptPath = args.get("script");
  int width = 1280, height = 800;
  parseSize(args.getOr("size", "1280x800"), width, height);
  if (width < 320 || height < 240 || width > 8192 || height > 8192)
    throw UsageError("--size must lie between 320x240 and 8192x8192");
  const std::string surface = args.getOr("surface", "");
  const std::string layout = args.getOr("layout", "auto");
  const std::string tensor = args.getOr("tensor", "");
  const bool force = args.flag("force");
  args.finish();
  if (!surface.empty()) parseSurfaceSpec(surface); // usage errors before a window opens
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
    if (force)
      for (ScriptStep& step : script->steps)
        if (auto* a = std::get_if<ui::Action>(&step.command)) {
          if (auto* shot = std::get_if<ui::Screenshot>(a)) shot->force = true;
          if (auto* camera = std::get_if<ui::SaveCamera>(a)) camera->force = true;
        }
  }

  ViewerWindowOptions o;
  o.inputs = inputs;
  o.surface = surface;
  o.layout = layout;
  o.tensor = tensor;
  o.width = width;
  o.height = height;
  o.script = script ? &*script : nullptr;
  return runViewerWindow(o);
}

} // namespace dtf::app
