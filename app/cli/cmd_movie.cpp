// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric movie`: a turntable, a slice sweep or an FA-threshold sweep of the fabric, headless, to an MP4,
// a GIF or numbered PNG frames, the advection state carried from frame to frame.
#include "app/cli/commands.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/formats/movie_writer.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "render/fabric_options.h"
#include "ui/session/movie_job.h"
#include "ui/session/surface_spec.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace dtf::app {

namespace {

const char* kIntro =
    "Renders a movie of the fabric on INPUT (a tensor volume, a DWI with --bval/--bvec, or a fibre set), headless: a "
    "turntable\n"
    "around the surface (a full turn about the superior axis), a sweep of slices through the data, or an\n"
    "FA-threshold sweep (the isosurface extracted again for every frame). The fabric stays coherent from "
    "frame\n"
    "to frame: each frame continues the previous frame's advection state, reprojected into the new view and\n"
    "onto the new surface, with --frame-iterations iterations of Eq. 12 (the paper's interactive mode); the\n"
    "first frame is a converged still. OUT.mp4 (H.264, yuv420p: even sizes) and OUT.gif are encoded by the\n"
    "`ffmpeg` program found on PATH; DIR/ receives frame_0000.png, frame_0001.png, ... The output appears "
    "only\n"
    "when complete (temporary file or directory, renamed). Progress on stderr.";

const char* kEpilogue =
    "Exit codes: 0 ok, 1 usage, 2 bad input (or no ffmpeg for MP4/GIF), 3 GL/render failure.";

} // namespace

const OptionTable& movieOptions() {
  static const OptionTable table = [] {
    using O = CliOption;
    const session::MovieRequest d;
    OptionTable t;
    t.command = "movie";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.intro = kIntro;
    t.epilogue = kEpilogue;
    t.options = {
        O::text("output", "OUT.mp4|OUT.gif|DIR/",
                "the movie: .mp4, .gif, or a directory of numbered PNG frames")
            .required()
            .under("Output"),
        O::text(
            "surface", "SPEC",
            "the turntable's surface: fa=T | slice=AXIS[:I] | plane=... | mesh=FILE (as `dtfabric render`)",
            "fa=0.25"),
        O::flag("turntable", "a full turn about the superior axis").under("Motion (one of)"),
        O::choice("sweep", "AXIS", {"axial", "coronal", "sagittal"}, "",
                  "slices along AXIS from the first to the last that holds data")
            .noDefault(),
        O::text("fa-sweep", "LO:HI", "FA isosurfaces from threshold LO to HI (each in (0, 1))"),
        O::integer("frames", "N", d.frames, closedRange(1, 10000), "number of frames").under("Frames"),
        O::number("fps", "F", 12, aboveUpTo(0, 240), "frames per second of the MP4/GIF"),
        O::text("size", "WxH", "frame size in pixels, 16x16 to 8192x8192 (even for MP4)", "512x512")
            .checkedBy(checkSize),
        O::flag("force", "replace an existing OUT (never an input)"),
        O::text("view", "V",
                "start view: axial|coronal|sagittal or superior|inferior|anterior|posterior|left|right")
            .defaultSays("turntable anterior; sweep the slice's own view; fa-sweep superior")
            .under("View")
            .hidden(),
        O::number("elevation", "DEG", d.elevationDeg, closedRange(-89, 89),
                  "turntable: camera height above the view's horizontal plane")
            .measuredIn("degrees")
            .hidden(),
        O::flag("neurological", "neurological display convention").hidden(),
        O::flag("perspective", "perspective instead of orthographic projection").hidden(),
        O::text("background", "B", "fa | md | FILE: grey where the fabric is absent (as `dtfabric render`)")
            .hidden(),
        O::text("background-window", "LO,HI", "grey ramp of the background").hidden(),
        layoutOption(LayoutNames::TensorOrFibre)
            .hidden()
            .under("Input (INPUT may also be a fibre set: peaks, a bedpostx folder, ...; woven in the fibre "
                   "colours, one thread field per population)"),
        pairedTensorOption("FA (--fa-sweep, FA modulation, --background fa|md)"),
        bvalOption().hidden(),
        bvecOption().hidden(),
        fitMaskOption().hidden(),
    };
    const std::vector<CliOption> furniture = furnitureOptions();
    t.options.insert(t.options.end(), furniture.begin(), furniture.end());
    std::vector<CliOption> fabric = fabricCliOptions();
    fabric.front().group = "Fabric (paper §2; --frame-iterations per movie frame)";
    t.options.insert(t.options.end(), fabric.begin(), fabric.end());
    return t;
  }();
  return table;
}

namespace {

void readFabric(ParsedOptions& args, render::FabricParams& p) {
  using K = render::FabricOption::Kind;
  for (const auto& o : render::fabricOptions()) {
    if (o.kind == K::OnOff) {
      if (args.flag(std::string("no-") + o.name)) o.set(p, 0);
    } else if (o.kind == K::Number || o.kind == K::Integer) {
      if (args.given(o.name)) o.set(p, args.number(o.name));
    } else if (const auto v = args.get(o.name)) { // named values (the colour mode)
      try {
        o.set(p, o.parse(*v));
      } catch (const UsageError& e) {
        throw UsageError(std::string("--") + e.what());
      }
    }
  }
}

void readMotion(ParsedOptions& args, session::MovieRequest& m) {
  const bool turntable = args.flag("turntable");
  const auto sweep = args.get("sweep");
  const auto faSweep = args.get("fa-sweep");
  if (int(turntable) + int(bool(sweep)) + int(bool(faSweep)) != 1)
    throw UsageError("give exactly one of --turntable, --sweep AXIS and --fa-sweep LO:HI");
  if (turntable) m.kind = session::MovieRequest::Kind::Turntable;
  if (sweep) {
    m.kind = session::MovieRequest::Kind::Sweep;
    m.axis = *sweep;
  }
  if (faSweep) {
    m.kind = session::MovieRequest::Kind::FaSweep;
    const auto colon = faSweep->find(':');
    char* end = nullptr;
    bool ok = colon != std::string::npos;
    if (ok) {
      const std::string a = faSweep->substr(0, colon), b = faSweep->substr(colon + 1);
      m.faLo = std::strtod(a.c_str(), &end);
      ok = !a.empty() && *end == '\0';
      m.faHi = std::strtod(b.c_str(), &end);
      ok = ok && !b.empty() && *end == '\0';
    }
    if (!ok || !(m.faLo > 0 && m.faLo < 1 && m.faHi > 0 && m.faHi < 1) || m.faLo == m.faHi)
      throw UsageError("--fa-sweep must be LO:HI, two different FA thresholds in (0, 1), not '" + *faSweep +
                       "'");
  }
}

} // namespace

int cmdMovie(const CommandArgs& argv) {
  ParsedOptions args(movieOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  session::MovieRequest m;
  session::RenderRequest& r = m.render;
  r.input = args.positional(0, "INPUT");
  const std::string output = args.required("output");
  r.output = output;
  readMotion(args, m);
  const auto surface = args.get("surface");
  if (surface && m.kind != session::MovieRequest::Kind::Turntable)
    throw UsageError("--surface is the turntable's; a sweep builds its own surfaces");
  r.surface = session::parseSurfaceSpec(surface.value_or("fa=0.25"));
  m.frames = args.integer("frames");
  const double fps = args.number("fps");
  parseSize(args.text("size"), r.width, r.height);
  const bool force = args.flag("force");
  if (const auto view = args.get("view")) r.view = render::parseView(*view);
  m.elevationDeg = args.number("elevation");
  r.neurological = args.flag("neurological");
  r.perspective = args.flag("perspective");
  r.background = args.text("background");
  r.backgroundWindow = args.text("background-window");
  r.layout = args.text("layout");
  r.tensor = args.text("tensor");
  if (!io::isFibreLayoutName(r.layout)) r.tensorOptions.layout = io::parseLayout(r.layout);
  r.tensorOptions.bval = args.text("bval");
  r.tensorOptions.bvec = args.text("bvec");
  r.tensorOptions.mask = args.text("mask");
  r.furniture = furnitureFrom(args);
  r.furniture.colourBar = false; // a movie draws no tracts
  readFabric(args, r.params);
  args.finish();

  const std::vector<std::string> inputs = {
      r.input,        r.tensorOptions.bval, r.tensorOptions.bvec, r.tensorOptions.mask,
      r.surface.file, r.background,         r.tensor};
  io::refuseMovieOverInputs(output, inputs);
  io::MovieWriter writer(output, r.width, r.height, fps, force); // checks ffmpeg, --force, the directory
  const auto t0 = std::chrono::steady_clock::now();
  session::runMovie(
      m, [&](int, const Image& frame) { writer.add(frame); },
      [&](int done, int total) {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr, "\rframe %d/%d (%.1f s)%s", done, total, s, done == total ? "\n" : "");
        std::fflush(stderr);
      });
  writer.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char line[160];
  std::snprintf(line, sizeof line, "%d frames %dx%d (%s) in %.2f s (%.3f s/frame)", writer.frames(), r.width,
                r.height, io::movieFormatName(writer.format()), seconds, seconds / writer.frames());
  logInfo(std::string(line) + " -> " + output);
  return 0;
}

} // namespace dtf::app
