// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric web INPUT -o DIR`: a self-contained folder (index.html, scripts, slice images) to browse the
// fabric of every slice in any browser from the file system (ui/session/web_page.h).
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "ui/session/web_page.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace dtf::app {

const OptionTable& webOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const session::WebPageRequest d;
    OptionTable t;
    t.command = "web";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.intro =
        "Writes a folder DIR that shows INPUT's fabric in any current browser, opened from the file system\n"
        "(DIR/index.html; no server, no network): every axial, coronal and sagittal slice that holds data,\n"
        "rendered headless once in the `render` look (radiological; the page mirrors it for the neurological\n"
        "convention), a slider per axis, Up/Down/PgUp/PgDn and A/C/S keys, zoom and pan, orientation letters\n"
        "and a probe (world mm, voxel, FA, principal direction) from a per-voxel table; then a 3D view of an\n"
        "FA isosurface (frames round it, the threads carried from frame to frame as in a movie: drag to turn)\n"
        "and an FA-threshold sweep of the isosurface with a slider. INPUT is a tensor volume or a DWI (fitted\n"
        "first). The folder is written beside DIR and renamed into place.";
    t.options = {
        O::text("output", "DIR", "the folder to write").required().under("Output"),
        O::flag("force", "replace an existing DIR that holds a page this command wrote (an empty one too)"),
        O::integer("size", "N", d.size, closedRange(16, 4096),
                   "pixels of each image's longer side (1024 for a sharp page on a high-density screen)")
            .measuredIn("pixels"),
        O::text("title", "TEXT", "the page's title").defaultSays("INPUT's file name"),
        O::text("background", "B",
                "fa | md | FILE: grey background where the fabric is absent (every slice of the grid is then "
                "rendered)")
            .under("Content"),
        O::text(
            "tracts", "FILE",
            ".tck, .trk, .trk.gz, .trx, .vtk or .vtp tracts: a second image set with the tracts near each "
            "slice, toggled in the page"),
        O::number("tracts-near", "MM", d.tractsNearMm, closedRange(0.1, 100),
                  "tract segments within MM of the slice's plane are drawn")
            .measuredIn("mm"),
        O::text("surface", "SPEC", "the 3D view's surface (as render --surface)", "fa=0.25").under("3D view"),
        O::integer("azimuths", "N", d.azimuths, closedRange(4, 360), "frames of the 3D view per turn"),
        O::text("elevations", "DEG[,DEG...]",
                "the 3D view's camera heights above the horizontal plane, degrees in [-89, 89] (a vertical drag "
                "moves between them)",
                "-15,20,55"),
        O::integer("fa-steps", "N", d.faSteps, closedRange(2, 64),
                   "thresholds of the FA sweep, evenly from 0.15 to 0.6"),
        O::flag("slices-only", "the slices alone: no 3D view, no FA sweep"),
        layoutOption(LayoutNames::Tensor).under("Input"),
        bvalOption(),
        bvecOption(),
        fitMaskOption(),
    };
    t.epilogue = "Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL/render failure.";
    return t;
  }();
  return table;
}

int cmdWeb(const CommandArgs& argv) {
  ParsedOptions args(webOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::WebPageRequest r;
  r.input = args.positional(0, "INPUT");
  r.output = args.required("output");
  r.force = args.flag("force");
  r.size = args.integer("size");
  r.title = args.text("title");
  r.background = args.text("background");
  r.tracts = args.text("tracts");
  r.tractsNearMm = args.number("tracts-near");
  r.surface = args.text("surface");
  r.azimuths = args.integer("azimuths");
  r.faSteps = args.integer("fa-steps");
  r.slicesOnly = args.flag("slices-only");
  r.elevationsDeg.clear();
  const std::string elevations = args.text("elevations");
  for (std::size_t start = 0; start <= elevations.size();) {
    const std::size_t comma = std::min(elevations.find(',', start), elevations.size());
    const std::string item = elevations.substr(start, comma - start);
    char* end = nullptr;
    const double e = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size())
      throw UsageError("--elevations must be degrees separated by commas, e.g. -15,20,55; got '" + elevations + "'");
    r.elevationsDeg.push_back(e);
    start = comma + 1;
  }
  r.tensorOptions.layout = io::parseLayout(args.text("layout"));
  r.tensorOptions.bval = args.text("bval");
  r.tensorOptions.bvec = args.text("bvec");
  r.tensorOptions.mask = args.text("mask");
  args.finish();
  r.onProgress = [](const std::string& s) { logInfo("web: " + s); };
  const session::WebPageResult w = session::writeWebPage(r);
  std::printf("%s: %d axial, %d coronal, %d sagittal slices, %d 3D frames, %d FA thresholds, %zu images, "
              "%.1f MB in %.1f s -> %s/index.html\n",
              r.input.c_str(), w.slices[0], w.slices[1], w.slices[2], w.frames3d, w.faFrames, w.images,
              double(w.bytes) / 1e6, w.seconds, r.output.c_str());
  return 0;
}

} // namespace dtf::app
