// `dtfabric render`: the fabric of paper §2 on a surface of a tensor volume, rendered headless to PNG.
#include "app/cli/args.h"
#include "app/cli/commands.h"
#include "app/scene/render_job.h"
#include "app/scene/surface_spec.h"
#include "app/scene/tensor_input.h"
#include "app/scene/tract_colouring.h"
#include "io/atomic_file.h"
#include "io/fibre_io.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/png_io.h"
#include "render/fabric_options.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

namespace dtf::app {

namespace {

const char* kHelp = R"(usage: dtfabric render INPUT -o OUT.png [OPTIONS]

Renders the fabric-like tensor texture (Eichelbaum et al.) on a surface of INPUT, headless (EGL, no
display needed), to an RGBA PNG. INPUT is any tensor volume dtfabric reads (FSL, MRtrix, SYMMATRIX,
DTI-TK layouts), or a DWI (4D with a volume count other than 6, or with --bval/--bvec) fitted first.
The same arguments always give the same PNG.

Surface (default: the middle axial slice, clipped to the data)
  --surface SPEC      fa=T            FA isosurface at T
                      iso=FILE:VALUE  isosurface of a scalar NIfTI volume
                      slice=AXIS[:I]  axial|coronal|sagittal slice I (default the middle)
                      plane=X,Y,Z:NX,NY,NZ | fibre=X0,Y0,Z0:X1,Y1,Z1 | mesh=FILE (PLY/OBJ/VTK/VTP, world mm)
  --fa T | --slice AXIS[:I] | --fibre-surface X0,Y0,Z0:X1,Y1,Z1 | --fibre-surface-voxel I0,J0,K0:I1,J1,K1
                      shorthands, as in `dtfabric surface`

View (world RAS: +x patient's right, +y anterior, +z superior)
  --view V            axial|coronal|sagittal (display views) or superior|inferior|anterior|posterior|left|right
                      (camera positions). Default: the slice's own view, else superior.
                        superior  from above, anterior up, patient's right on the image RIGHT
                        inferior  from below, anterior up, patient's right on the image LEFT
                        anterior  from the front, superior up, patient's right on the image LEFT
                        posterior from behind, superior up, patient's right on the image RIGHT
                        left      from the patient's left, superior up, anterior on the image LEFT
                        right     from the patient's right, superior up, anterior on the image RIGHT
                      Display views are RADIOLOGICAL by default (patient's right on the image left):
                        axial = inferior, coronal = anterior, sagittal = left (anterior on the left).
  --neurological      neurological display convention: axial = superior, coronal = posterior,
                      sagittal = right. Has no effect on the plain camera positions.
  --perspective       perspective instead of orthographic projection
  --size WxH          image size in pixels (default 768x768)

Fabric (paper §2)
)";

const char* kHelpTail = R"(
Background (grey where the fabric is absent; slices and planes then cover the whole grid, not only the data)
  --background B      fa | md | FILE (any scalar NIfTI on any grid, e.g. a T1 in world RAS)
  --background-window LO,HI   grey ramp (default: fa 0,1; md 0,0.003 mm^2/s; FILE its 1st..99th percentile)

Tracts (drawn over the fabric, depth-tested against it, DEC coloured by tangent: x red, y green, z blue)
  --tracts FILE       .tck, .trk, .trk.gz, .trx, .vtk or .vtp tracts (world RAS mm)
  --tracts-color NAME colour by this per-point or per-streamline value (viridis; a bar at the right edge,
                      its range printed) instead of DEC
  --tracts-range LO,HI  the value range of the colour map (default: the value's minimum..maximum)
  --tracts-group G[,G]  show only the streamlines of these groups (TRX groups/)
  --tracts-near MM    show only tract segments within MM of the surface (default 3; 0 = all). On a planar
                      surface (slice, plane) this is a slab of half-width MM around the plane.
  --tracts-slab MM    also clip to a slab of half-width MM around the surface's plane (curved surfaces:
                      the plane through the centre of the surface facing the camera, as the viewer's clip)
  --tracts-slab-depth MM  curved surfaces: move that plane MM away from the viewer (default 0)
  --tract-width PX    tube width in pixels (default 2)
  --split MODE        two linked panes (same camera) side by side in one 2W x H image:
                        tracts          fabric alone | fabric with the tracts (needs --tracts)
                        colour          medical | engineering colour
                        surface=SPEC    the --surface | this second surface
                        input=FILE      INPUT | a second tensor/DWI file, same surface spec; a fibre set as
                                        FILE shows a tensor INPUT's principal direction beside its fibres

Input (INPUT may also be a fibre set: MRtrix sh2peaks or DIPY peaks file, FSL bedpostx folder or dyadsN file,
DSI Studio .fib.gz, FSL dtifit set with V1 but no L1-L3; the last two bring their own FA)
  --layout L          tensor layout override (fsl, mrtrix, symmatrix, dtitk) or fibre layout (mrtrix-peaks,
                      dipy-peaks, bedpostx)
  --tensor F          fibre sets: a tensor volume on the same grid for FA (fa= surfaces, FA modulation,
                      --background fa|md); without it (or the file's own FA) those are refused
  --bval F --bvec F   treat INPUT as a DWI and fit tensors (WLS)
  --mask F            DWI fit mask
  --force             overwrite an existing OUT.png (never an input)

Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL/render failure.
)";

// The options of render/fabric_options.h as flags: --NAME VALUE, and --no-NAME for the on/off ones.
void readFabricOptions(Args& args, render::FabricParams& p) {
  for (const auto& o : render::fabricOptions()) {
    if (o.kind == render::FabricOption::Kind::OnOff) {
      if (args.flag(std::string("no-") + o.name)) o.set(p, 0);
    } else if (auto v = args.get(o.name)) {
      try {
        o.set(p, o.parse(*v));
      } catch (const UsageError& e) {
        throw UsageError(std::string("--") + e.what());
      }
    }
  }
}

} // namespace

int cmdRender(const CommandArgs& argv) {
  std::set<std::string> flags = {"help", "neurological", "perspective", "force"};
  for (const auto& o : render::fabricOptions())
    if (o.kind == render::FabricOption::Kind::OnOff) flags.insert(std::string("no-") + o.name);
  Args args(argv, flags);
  if (args.flag("help")) {
    std::fputs(kHelp, stdout);
    std::fputs(render::fabricOptionsHelp().c_str(), stdout);
    std::fputs(kHelpTail, stdout);
    return 0;
  }
  const std::string input = args.positional(0, "INPUT");
  if (args.positionals().size() > 1) throw UsageError("unexpected argument '" + args.positionals()[1] + "'");
  const std::string output = args.getOr("output", "");
  if (output.empty()) throw UsageError("missing -o OUT.png");
  int width = 768, height = 768;
  if (auto s = args.get("size")) parseSize(*s, width, height);
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    throw UsageError("--size must be between 16x16 and 8192x8192");
  SurfaceSpec spec = parseSurfaceSpec(surfaceArgument(args).value_or("slice=axial"));
  const bool neurological = args.flag("neurological");
  render::StandardView view = args.get("view") ? render::parseView(*args.get("view")) : defaultView(spec);
  const bool perspective = args.flag("perspective");

  render::FabricParams p;
  // A fibre set's default colour mode is fibres: remember whether --color was given.
  const std::string colour = args.getOr("color", "");
  readFabricOptions(args, p);

  TensorInputOptions in;
  const std::string layoutText = args.getOr("layout", "auto");
  const std::string tensorPath = args.getOr("tensor", "");
  if (!io::isFibreLayoutName(layoutText)) in.layout = io::parseLayout(layoutText);
  in.bval = args.getOr("bval", "");
  in.bvec = args.getOr("bvec", "");
  in.mask = args.getOr("mask", "");
  const bool force = args.flag("force");
  const std::string tractsPath = args.getOr("tracts", "");
  TractColouring colouring;
  colouring.value = args.getOr("tracts-color", "");
  if (auto r = args.get("tracts-range")) colouring.range = parseTractRange(*r);
  if (auto g = args.get("tracts-group")) {
    std::stringstream ss(*g);
    for (std::string name; std::getline(ss, name, ',');)
      if (!name.empty()) colouring.groups.push_back(name);
  }
  if ((!colouring.value.empty() || colouring.range || !colouring.groups.empty()) && tractsPath.empty())
    throw UsageError("--tracts-color, --tracts-range and --tracts-group need --tracts FILE");
  const double tractsNear = args.getDouble("tracts-near", 3.0);
  if (!(tractsNear >= 0 && tractsNear <= 1000)) throw UsageError("--tracts-near must be in [0, 1000] mm");
  const double tractsSlab = args.getDouble("tracts-slab", 0.0);
  if (!(tractsSlab >= 0 && tractsSlab <= 1000)) throw UsageError("--tracts-slab must be in [0, 1000] mm");
  const double tractsSlabDepth = args.getDouble("tracts-slab-depth", 0.0);
  if (!(std::abs(tractsSlabDepth) <= 1000))
    throw UsageError("--tracts-slab-depth must be in [-1000, 1000] mm");
  const std::string backgroundArg = args.getOr("background", "");
  const std::string backgroundWindow = args.getOr("background-window", "");
  const double tractWidth = args.getDouble("tract-width", 2.0);
  if (!(tractWidth > 0 && tractWidth <= 32)) throw UsageError("--tract-width must be in (0, 32] pixels");
  const SplitMode split = args.get("split") ? parseSplitMode(*args.get("split")) : SplitMode{};
  if (split.kind == SplitMode::Kind::Tracts && tractsPath.empty())
    throw UsageError("--split tracts needs --tracts FILE");
  args.finish();

  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(output) && fs::equivalent(output, input, ec))
    throw UsageError("output " + output + " is the input: refusing to overwrite it");
  io::refuseOverwritingInput(output, {in.bval, in.bvec, in.mask, spec.file, tractsPath, split.value, backgroundArg,
                                     tensorPath});
  if (!force && fs::exists(output)) throw InputError(output + " exists (use --force to overwrite it)");

  const auto t0 = std::chrono::steady_clock::now();
  RenderRequest request;
  request.input = input;
  request.tensorOptions = in;
  request.layout = layoutText;
  request.tensor = tensorPath;
  request.surface = spec;
  request.view = view;
  request.neurological = neurological;
  request.perspective = perspective;
  request.width = width;
  request.height = height;
  request.params = p;
  request.colourGiven = !colour.empty();
  request.colourName = colour;
  request.background = backgroundArg;
  request.backgroundWindow = backgroundWindow;
  request.tracts = tractsPath;
  request.colouring = colouring;
  request.tractsNear = tractsNear;
  request.tractsSlab = tractsSlab;
  request.tractsSlabDepth = tractsSlabDepth;
  request.tractWidth = tractWidth;
  request.split = split;
  request.output = output;
  const RenderResult result = runRender(request);
  const Image& image = result.image;
  io::writePng(output, image);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  logInfo("rendered " + result.surface + " (" + std::to_string(result.triangles) +
          " triangles), view " + render::viewName(view) + (neurological ? " (neurological)" : "") + ", " +
          std::to_string(result.iterations) + " advection iterations, " + std::to_string(width) +
          "x" + std::to_string(height) + " -> " + output + " in " + std::to_string(seconds).substr(0, 5) +
          " s");
  return 0;
}

} // namespace dtf::app
