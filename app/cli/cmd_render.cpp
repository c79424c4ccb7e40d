// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric render`: the fabric of paper §2 on a surface of a tensor volume, rendered headless to PNG.
#include "app/command/args.h"
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "ui/session/render_job.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/tract_colouring.h"
#include "io/formats/atomic_file.h"
#include "io/formats/fibre_io.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/png_io.h"
#include "render/fabric_options.h"

#include <chrono>
#include <filesystem>
#include <sstream>

namespace dtf::app {

namespace {

const char* kIntro =
    "Renders the fabric-like tensor texture (Eichelbaum et al.) on a surface of INPUT, headless (EGL, no\n"
    "display needed), to an RGBA PNG. INPUT is any tensor volume dtfabric reads (FSL, MRtrix, SYMMATRIX,\n"
    "DTI-TK layouts), or a DWI (4D with a volume count other than 6, or with --bval/--bvec) fitted first.\n"
    "The same arguments always give the same PNG.";

const char* kViews = "Views (world RAS: +x patient's right, +y anterior, +z superior)\n"
                     "  superior  from above, anterior up, patient's right on the image RIGHT\n"
                     "  inferior  from below, anterior up, patient's right on the image LEFT\n"
                     "  anterior  from the front, superior up, patient's right on the image LEFT\n"
                     "  posterior from behind, superior up, patient's right on the image RIGHT\n"
                     "  left      from the patient's left, superior up, anterior on the image LEFT\n"
                     "  right     from the patient's right, superior up, anterior on the image RIGHT\n"
                     "Display views are RADIOLOGICAL by default (patient's right on the image left):\n"
                     "  axial = inferior, coronal = anterior, sagittal = left (anterior on the left).\n"
                     "\n"
                     "Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL/render failure.";

// The fabric rows (render/fabric_options.h), --color and --fibre-threshold shown in the usage line.
std::vector<CliOption> fabricRows() {
  std::vector<CliOption> rows = fabricCliOptions();
  for (auto& o : rows)
    if (o.name == "color" || o.name == "fibre-threshold") o.synopsis = CliOption::Synopsis::Optional;
  rows.front().group = "Fabric (paper §2)";
  return rows;
}

std::vector<CliOption> outputSurfaceAndViewRows(const session::RenderRequest& d) {
  using O = CliOption;
  std::vector<CliOption> rows = {
      O::text("output", "OUT.png", "the RGBA PNG to write").required().under("Output"),
      O::flag("force", "overwrite an existing OUT.png (never an input)").hidden(),
      O::text("surface", "SPEC",
              "fa=T: FA isosurface at T (windowed-sinc smoothed, 15 iterations, no vertex moved more than 0.5 voxel)\n"
              "iso=FILE:VALUE: isosurface of a scalar NIfTI volume\n"
              "slice=AXIS[:I]: axial|coronal|sagittal slice I (default the middle)\n"
              "plane=X,Y,Z:NX,NY,NZ | fibre=X0,Y0,Z0:X1,Y1,Z1 | mesh=FILE (PLY/OBJ/VTK/VTP, world mm)")
          .under("Surface (default: the middle axial slice, clipped to the data)"),
      O::text("fa", "T", "shorthand for --surface fa=T, as in `dtfabric surface`").hidden(),
      O::text("slice", "AXIS[:I]", "shorthand for --surface slice=AXIS[:I]").hidden(),
      O::text("fibre-surface", "X0,Y0,Z0:X1,Y1,Z1", "stream surface of e1 seeded on a line (world mm)")
          .hidden(),
      O::text("fibre-surface-voxel", "I0,J0,K0:I1,J1,K1", "the same in voxel indices").hidden(),
      O::text("view", "V",
              "axial|coronal|sagittal (display views) or superior|inferior|anterior|posterior|left|right "
              "(camera positions; see Views below)")
          .defaultSays("the slice's own view, else superior")
          .under("View (world RAS: +x patient's right, +y anterior, +z superior)"),
      O::flag("neurological",
              "neurological display convention: axial = superior, coronal = posterior, sagittal = right. Has "
              "no effect on the plain camera positions")
          .hidden(),
      O::flag("perspective", "perspective instead of orthographic projection").hidden(),
      O::text("size", "WxH",
              "image size in pixels, 16x16 to 8192x8192; above 768 the fabric keeps the threads of a 768 px "
              "image (noise cell and step scale with the size): larger is sharper, not finer",
              std::to_string(d.width) + "x" + std::to_string(d.height))
          .checkedBy(checkSize)
          .hidden(),
      O::integer("supersample", "N", d.supersample, closedRange(1, 4),
                 "render at N times the size and box-filter down: anti-aliased thread edges, the same fabric "
                 "(noise cell, advection step, silhouette and tract widths scale with N)")
          .under("Figure"),
  };
  const std::vector<CliOption> furniture = furnitureOptions();
  rows.insert(rows.end(), furniture.begin(), furniture.end());
  return rows;
}

std::vector<CliOption> backgroundAndTractRows(const session::RenderRequest& d) {
  using O = CliOption;
  return {
      O::text("background", "B", "fa | md | FILE (any scalar NIfTI on any grid, e.g. a T1 in world RAS)")
          .under(
              "Background (grey where the fabric is absent; slices and planes then cover the whole grid, not "
              "only the data)"),
      O::text("background-window", "LO,HI", "grey ramp")
          .defaultSays("fa 0,1; md 0,0.003 mm^2/s; FILE its 1st..99th percentile")
          .hidden(),
      O::text("fabric-along", "TRACTS[:MM]",
              "draw the fabric only within MM (default 2) mm of the streamlines of a tract file (any format "
              "--tracts reads), the background elsewhere (FA when --background is not given): one bundle's "
              "texture alone on a slice or an FA isosurface"),
      O::text(
          "uncertainty", "CONE",
          "a 95 % cone-of-uncertainty map in degrees (fit --bootstrap N --cone CONE; any grid) or a "
          "bedpostx folder with merged_th1samples/merged_ph1samples: the threads fray as the cone widens "
          "(--fray W, --fray-cells N) while keeping the data's mean direction; a legend shows the look per "
          "cone")
          .under("Uncertainty"),
      O::text("tracts", "FILE", ".tck, .trk, .trk.gz, .trx, .vtk or .vtp tracts (world RAS mm)")
          .under("Tracts (drawn over the fabric, depth-tested against it, DEC coloured by tangent: x red, y "
                 "green, z blue)"),
      O::text("tracts-color", "NAME",
              "colour by this per-point or per-streamline value (viridis; a bar at the right edge, its range "
              "printed) instead of DEC; `node`: by the node index (0..99) along the bundle oriented and "
              "resampled as `dtfabric profile` does"),
      O::text("tracts-range", "LO,HI", "the value range of the colour map")
          .defaultSays("the value's minimum..maximum"),
      O::text("tracts-group", "G[,G]", "show only the streamlines of these groups (TRX groups/)"),
      O::number("tracts-near", "MM", d.tractsNear, closedRange(0, 1000),
                "show only tract segments within MM of the surface (0 = all). On a planar surface (slice, "
                "plane) this is a slab of half-width MM around the plane")
          .measuredIn("mm")
          .hidden(),
      O::number("tracts-slab", "MM", d.tractsSlab, closedRange(0, 1000),
                "also clip to a slab of half-width MM around the surface's plane (curved surfaces: the plane "
                "through the centre of the surface facing the camera, as the viewer's clip; 0 = none)")
          .measuredIn("mm")
          .hidden(),
      O::number("tracts-slab-depth", "MM", d.tractsSlabDepth, closedRange(-1000, 1000),
                "curved surfaces: move that plane MM away from the viewer")
          .measuredIn("mm")
          .hidden(),
      O::number("tract-width", "PX", d.tractWidth, aboveUpTo(0, 32), "tube width")
          .measuredIn("pixels")
          .hidden(),
      O::text("split", "MODE",
              "two linked panes (same camera) side by side in one 2W x H image:\n"
              "tracts: fabric alone | fabric with the tracts (needs --tracts)\n"
              "colour: medical | engineering colour\n"
              "surface=SPEC: the --surface | this second surface\n"
              "input=FILE: INPUT | a second tensor/DWI file, same surface spec; a fibre set as FILE shows a "
              "tensor INPUT's principal direction beside its fibres"),
  };
}

// The input rows (app/command/options.h); the layout's default, auto, is RenderRequest's.
std::vector<CliOption> inputRows() {
  return {
      layoutOption(LayoutNames::TensorOrFibre)
          .hidden()
          .under(
              "Input (INPUT may also be a fibre set: MRtrix sh2peaks or DIPY peaks file, FSL bedpostx folder "
              "or dyadsN file,\nDSI Studio .fib.gz, FSL dtifit set with V1 but no L1-L3; the last two bring "
              "their own FA)"),
      pairedTensorOption(
          "FA (fa= surfaces, FA modulation, --background fa|md); without it (or the file's own "
          "FA) those are refused"),
      bvalOption().hidden(),
      bvecOption().hidden(),
      fitMaskOption().hidden(),
  };
}

} // namespace

const OptionTable& renderOptions() {
  static const OptionTable table = [] {
    const session::RenderRequest d; // the defaults
    OptionTable t;
    t.command = "render";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.intro = kIntro;
    t.epilogue = kViews;
    for (const auto& part :
         {outputSurfaceAndViewRows(d), fabricRows(), backgroundAndTractRows(d), inputRows()})
      t.options.insert(t.options.end(), part.begin(), part.end());
    return t;
  }();
  return table;
}

namespace {

void readSurfaceAndView(ParsedOptions& args, session::RenderRequest& r) {
  parseSize(args.text("size"), r.width, r.height);
  r.surface = session::parseSurfaceSpec(surfaceArgument(args).value_or("slice=axial"));
  r.neurological = args.flag("neurological");
  const auto view = args.get("view");
  r.view = view ? render::parseView(*view) : session::defaultView(r.surface);
  r.perspective = args.flag("perspective");
  r.supersample = args.integer("supersample");
  r.furniture = furnitureFrom(args);
}

// The fabric options: --NAME VALUE, and --no-NAME for the on/off ones. A fibre set's default colour mode is
// fibres, so whether --color was given is kept.
void readFabricOptions(ParsedOptions& args, session::RenderRequest& r) {
  for (const auto& o : render::fabricOptions()) {
    if (o.kind == render::FabricOption::Kind::OnOff) {
      if (args.flag(std::string("no-") + o.name)) o.set(r.params, 0);
    } else if (o.kind == render::FabricOption::Kind::Choice) {
      const auto v = args.get(o.name);
      if (!v) continue;
      try {
        o.set(r.params, o.parse(*v));
      } catch (const UsageError& e) {
        throw UsageError(std::string("--") + e.what());
      }
      if (std::string(o.name) == "color") {
        r.colourGiven = true;
        r.colourName = *v;
      }
    } else if (args.given(o.name)) {
      o.set(r.params, args.number(o.name));
    }
  }
}

void readInputOptions(ParsedOptions& args, session::RenderRequest& r) {
  r.layout = args.text("layout");
  r.tensor = args.text("tensor");
  if (!io::isFibreLayoutName(r.layout)) r.tensorOptions.layout = io::parseLayout(r.layout);
  r.tensorOptions.bval = args.text("bval");
  r.tensorOptions.bvec = args.text("bvec");
  r.tensorOptions.mask = args.text("mask");
}

void readTractOptions(ParsedOptions& args, session::RenderRequest& r) {
  r.tracts = args.text("tracts");
  session::TractColouring& colouring = r.colouring;
  colouring.value = args.text("tracts-color");
  if (auto range = args.get("tracts-range")) colouring.range = session::parseTractRange(*range);
  if (auto g = args.get("tracts-group")) {
    std::stringstream ss(*g);
    for (std::string name; std::getline(ss, name, ',');)
      if (!name.empty()) colouring.groups.push_back(name);
  }
  if ((!colouring.value.empty() || colouring.range || !colouring.groups.empty()) && r.tracts.empty())
    throw UsageError("--tracts-color, --tracts-range and --tracts-group need --tracts FILE");
  r.tractsNear = args.number("tracts-near");
  r.tractsSlab = args.number("tracts-slab");
  r.tractsSlabDepth = args.number("tracts-slab-depth");
  r.background = args.text("background");
  r.backgroundWindow = args.text("background-window");
  r.uncertainty = args.text("uncertainty");
  if (auto along = args.get("fabric-along")) r.fabricAlong = session::parseFabricAlong(*along);
  r.tractWidth = args.number("tract-width");
  const auto split = args.get("split");
  r.split = split ? session::parseSplitMode(*split) : session::SplitMode{};
  if (r.split.kind == session::SplitMode::Kind::Tracts && r.tracts.empty())
    throw UsageError("--split tracts needs --tracts FILE");
}

// Refuses to write over an input, or over an existing file without --force.
void checkOutput(const session::RenderRequest& r, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(r.output) && fs::equivalent(r.output, r.input, ec))
    throw UsageError("output " + r.output + " is the input: refusing to overwrite it");
  const session::TensorInputOptions& in = r.tensorOptions;
  io::refuseOverwritingInput(r.output, {in.bval, in.bvec, in.mask, r.surface.file, r.tracts, r.split.value,
                                        r.background, r.tensor, r.uncertainty, r.fabricAlong.path});
  if (!force && io::outputExists(r.output))
    throw InputError(r.output + " exists (use --force to overwrite it)");
}

void logRendered(const session::RenderRequest& r, const session::RenderResult& result, double seconds) {
  logInfo("rendered " + result.surface + " (" + std::to_string(result.triangles) + " triangles), view " +
          render::viewName(*r.view) + (r.neurological ? " (neurological)" : "") + ", " +
          std::to_string(result.iterations) + " advection iterations, " + std::to_string(r.width) + "x" +
          std::to_string(r.height) + " -> " + r.output + " in " + std::to_string(seconds).substr(0, 5) +
          " s");
}

} // namespace

int cmdRender(const CommandArgs& argv) {
  ParsedOptions args(renderOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::RenderRequest request;
  request.input = args.positional(0, "INPUT");
  request.output = args.required("output");
  readSurfaceAndView(args, request);
  readFabricOptions(args, request);
  readInputOptions(args, request);
  const bool force = args.flag("force");
  readTractOptions(args, request);
  args.finish();
  checkOutput(request, force);
  if (!request.uncertainty.empty() && request.params.look == render::Look::Anatomy)
    logInfo("the anatomy look fades the fabric where FA is low, which is where the cone is widest: the "
            "fraying shows in white matter; --look plain shows it everywhere");

  const auto t0 = std::chrono::steady_clock::now();
  const session::RenderResult result = session::runRender(request);
  io::writePng(request.output, result.image);
  logRendered(request, result, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

} // namespace dtf::app
