// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "app/cli/manual.h"
#include "app/command/options.h"
#include "app/viewer/view_script.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <cstdio>
#include <cstring>
#include <iostream>

#ifndef DTF_VERSION
#define DTF_VERSION "unknown"
#endif

namespace dtf::app {

const std::vector<Command>& commands() {
  static const std::vector<Command> list = {
      {"info", nullptr,
       "describe a tensor, scalar or DWI volume, or a tractogram (header, counts, lengths, data)",
       "file format and why, header, orientation, detected tensor layout and why, value ranges, FA statistics; "
       "one voxel's world tensor, eigen-system and metrics (with `--uncertainty CONE`, its cone). For a "
       "tractogram (.tck, .trk, .trk.gz, .trx, .vtk, "
       ".vtp): format, header facts (space, voxel order, dimensions, affine), streamline and point counts, "
       "lengths, per-streamline/per-point data with shapes and ranges, groups. For a fibre set (MRtrix or DIPY "
       "peaks, FSL bedpostx, DSI Studio `.fib.gz`, FSL dtifit V1 without L1–L3): layout and frame with the reason, "
       "populations per voxel; one voxel's fibres "
       "(`\"fibres\": [{\"direction\": [x, y, z], \"amplitude\": a}, …]`, unit world RAS, strongest first) "
       "beside the file's own FA (`dti_fa`, dtifit `FA`) or a paired tensor's (`--tensor`) FA and eigenvectors",
       cmdInfo, infoOptions},
      {"fit", nullptr,
       "fit diffusion tensors to a DWI with bval/bvec (WLS or OLS)",
       "fit tensors to a DWI (WLS by default; automatic mask when none is given); an MRtrix DWI with "
       "`dw_scheme` or a DSI Studio `.src.gz` needs no bval/bvec; OUT `.nii[.gz]`, `.mif[.gz]`/`.mih` or `.nrrd`; "
       "`--bootstrap N --cone CONE`: a wild bootstrap writing the 95 % cone of uncertainty of the principal "
       "direction (degrees) and `--fa-sd` FA's spread",
       cmdFit, fitOptions},
      {"phantom", nullptr,
       "write an analytic tensor field (sphere, bretzel5, constant, crossing, brain)",
       "analytic fields: `sphere`, `bretzel5` (paper §3.1), `constant`, `crossing`, `brain`; `crossing` and "
       "`constant` also as fibre sets (`--layout mrtrix-peaks|dipy-peaks|bedpostx`)",
       cmdPhantom, phantomOptions},
      {"surface", nullptr,
       "extract an FA isosurface, slice or fibre-following surface to a mesh, with its quality",
       "FA isosurface, slice, oblique plane or fibre-following surface as a mesh, with its quality figure "
       "(FA-weighted mean |e1·n|)",
       cmdSurface, surfaceOptions},
      {"render", nullptr,
       "render the fabric on a surface to PNG, headless",
       "the fabric, headless; for a fibre set (peaks) the multi-population fabric, each population in its own "
       "DEC colour, strongest on top (`--split input=PEAKS` beside a tensor INPUT: DTI beside the fibres on one "
       "camera, the peaks pane with the tensor's FA); tracts over it in DEC colours or coloured by a "
       "per-point or per-streamline value (viridis, a colour bar at the right edge, the range printed), only "
       "the streamlines of the named groups; "
       "`--uncertainty CONE` (a cone map or a bedpostx folder): threads fray as the cone widens, with a legend",
       cmdRender, renderOptions},
      {"movie", nullptr,
       "a turntable, slice sweep or FA-threshold sweep of the fabric to MP4, GIF or PNG frames, headless",
       "a turntable around a surface, a sweep of slices through the data or an FA-threshold sweep (the "
       "isosurface extracted per frame), the advection state carried from frame to frame (no re-seeded "
       "flicker); MP4 (H.264) and GIF through the `ffmpeg` program on PATH, or numbered PNG frames into `DIR/`; "
       "atomic, never over an input",
       cmdMovie, movieOptions},
      {"track", nullptr,
       "deterministic tensor tractography to .tck/.trk/.trx/.vtk",
       "deterministic tensor tractography (RK4, FA stop, angle limit, length range)", cmdTrack,
       trackOptions},
      {"convert", nullptr,
       "convert tractograms between .tck, .trk, .trk.gz, .trx, .vtk and .vtp",
       "any supported tractogram to any other, keeping data and groups where the target holds them (warnings "
       "name what is dropped); atomic, never over an input",
       cmdConvert, convertOptions},
      {"select", nullptr,
       "ROI selection of streamlines: keep those through include regions and no exclude region (as tckedit)",
       "keeps the streamlines through every include region (spheres, boxes, masks or atlas labels on any grid; "
       "ordered includes entered in order) and no exclude region, on the stored vertices as MRtrix's `tckedit` "
       "(`--ends-only`, `--precise` for the segments between vertices, `--min-length`/`--max-length`); regions "
       "from flags and a region set file (`--roi`, as the viewer saves it); every value and group kept; "
       "`--as-group NAME` adds the selection as a TRX group; .tck to .tck in place; atomic, never over an input",
       cmdSelect, selectOptions},
      {"profile", nullptr,
       "tract profiles (tractometry): FA or any scalar along bundles, as DIPY afq_profile and pyAFQ",
       "tract profiles as DIPY `afq_profile` and pyAFQ: each file (or TRX group) a bundle, oriented alike, "
       "resampled to N nodes by arc length, scalars (fa/md/ad/rd of `--tensor`, or `NAME=IMAGE`) sampled "
       "trilinearly; per node the gauss-weighted (or mean, median) value, sd, a seeded bootstrap 95 % interval, "
       "the core position and the streamline count, as one tidy TSV (`--json`: the same rows); `--plot` a "
       "figure (PNG or SVG) with a panel per scalar and a band per bundle",
       cmdProfile, profileOptions},
      {"compare", nullptr,
       "angle between tracts and the fabric direction (or nearest fibre population) on a surface",
       "angle between tracts near a surface and the fabric's principal direction there; for a fibre set (peaks), "
       "the nearest fibre population in the surface",
       cmdCompare, compareOptions},
      {"check", nullptr,
       "orientation check: a flipped or permuted gradient table, tensor frame or fibre-set frame, and its fix",
       "orientation check: scores the 24 signed axis permutations of a DWI's gradient table (or a tensor file's "
       "directions, or a fibre set's first fibres in its stored frame) by white-matter fibre coherence; verdict `ok`, `corrected` (with M: corrected bvec = M · "
       "given bvec) or `inconclusive`; `--sheet` draws the fabric evidence, `--fix-bvec` writes the corrected "
       "FSL table",
       cmdCheck, checkOptions},
      {"bids", nullptr,
       "BIDS App: per-run fit, orientation check and figures; group table and HTML report",
       "BIDS App: per diffusion run a tensor fit, the orientation check, four fabric figures (+ the check's "
       "contact sheet when not `ok`) and a metrics JSON under `OUTPUT_DIR/sub-XX/[ses-YY/]dwi/`; the group level "
       "writes `group.tsv` and `group_report.html` (see [Cohorts](#cohorts-bids))",
       cmdBids, bidsOptions},
      {"web", nullptr,
       "write a self-contained web page (folder) to browse every slice's fabric, a 3D view and an FA sweep",
       "a folder that opens from the file system in any current browser (no server, no network): the fabric "
       "of every axial, coronal and sagittal slice in the `render` look, a slider per axis, the viewer's keys, "
       "zoom and pan, orientation letters, the radiological/neurological choice, a probe (world mm, voxel, FA, "
       "principal direction) and, with `--tracts`, a tract overlay toggle; a 3D view of an FA isosurface "
       "turned by dragging (frames rendered with the movie's carried threads) and an FA-threshold sweep with "
       "a slider; `--slices-only` for the slices alone",
       cmdWeb, webOptions},
      {"view", nullptr, "open the viewer (GLFW window with ImGui panels)",
       "the viewer: GLFW window, Dear ImGui panels (Data, Surface, Fabric, Fibres for fibre sets, View, Tracts), "
       "status bar with the voxel under the cursor (its tensor and fibres); `--script` replays actions for reproducible figures (see below; `--force`: its "
       "screenshots, camera and tract files may replace existing files)",
       cmdView, viewOptions},
      {"bench", nullptr, nullptr, nullptr, cmdBench}, // synopsis and summaries from app/bench/bench.h
      {"help", nullptr, "this list; --markdown: the command and script tables of the README and the reference",
       "this list; `--markdown`: the command and script tables of the README and the reference", cmdHelp,
       helpOptions},
  };
  return list;
}

namespace {
std::string joinedBenchNames() {
  std::string names;
  for (const auto& b : benchmarks())
    names += (names.empty() ? "" : ", ") + std::string(b.name);
  return names;
}
} // namespace

std::string summaryOf(const Command& c) {
  return c.summary ? c.summary : "benchmarks: " + joinedBenchNames();
}
std::string synopsisOf(const Command& c) {
  if (c.options) return c.options().synopsis();
  if (c.synopsis) return c.synopsis;
  std::string names;
  for (const auto& b : benchmarks())
    names += (names.empty() ? "" : "|") + std::string(b.name);
  return names + " [--json]";
}
std::string descriptionOf(const Command& c) {
  if (c.description) return c.description;
  std::string d = "benchmarks:";
  for (const auto& b : benchmarks())
    d += std::string(" `") + b.name + "` " + b.summary + ";";
  d.back() = '.';
  return d;
}

namespace {
// A markdown table cell: '|' escaped.
std::string cell(const std::string& text) {
  std::string out;
  for (char ch : text) {
    if (ch == '|') out += '\\';
    out += ch;
  }
  return out;
}

void printUsage() {
  std::printf("usage: dtfabric COMMAND [ARGS]\n\ncommands:\n");
  for (const auto& c : commands()) std::printf("  %-9s %s\n", c.name, summaryOf(c).c_str());
  std::printf("\n`dtfabric COMMAND --help` describes each command; `dtfabric --version` prints the version.\n"
              "Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL/render failure.\n");
}
} // namespace

std::string markdownTables() {
  // README.md's short table: each command's one line and where its whole help is.
  std::string out = "| command | what it does | all its options |\n|---|---|---|\n";
  for (const auto& c : commands()) {
    const std::string name = c.name;
    out += "| `dtfabric " + name + "` | " + cell(summaryOf(c)) + " | `dtfabric " + name +
           " --help`, `man dtfabric-" + name + "` |\n";
  }
  // The reference's table: the synopsis and the whole description.
  out += "\n| command | what it does |\n|---|---|\n";
  for (const auto& c : commands())
    out += "| `dtfabric " + std::string(c.name) + " " + cell(synopsisOf(c)) + "` | " + cell(descriptionOf(c)) +
           " |\n";
  out += "\n| line | does |\n|---|---|\n";
  for (const auto& c : scriptCommands())
    out += "| `" + std::string(c.name) + (*c.args ? " " : "") + cell(c.args) + "` | " + cell(c.help) + " |\n";
  return out;
}

const OptionTable& helpOptions() {
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "help";
    t.intro = "Lists the commands; `dtfabric COMMAND --help` describes each.";
    t.options = {CliOption::flag("markdown",
                                 "the command and script tables of the README and the reference (markdown)"),
                 // What the build installs (app/cli/manual.h).
                 CliOption::text("man", "NAME", "the roff source of man page NAME (dtfabric, dtfabric-render, ...)")
                     .internalOnly(),
                 CliOption::flag("man-pages", "the names of the man pages, one a line").internalOnly(),
                 CliOption::flag("bash-completion", "the bash completion script").internalOnly()};
    return t;
  }();
  return table;
}

int cmdHelp(const CommandArgs& argv) {
  ParsedOptions args(helpOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const bool markdown = args.flag("markdown");
  const auto man = args.get("man");
  const bool manPages = args.flag("man-pages"), completion = args.flag("bash-completion");
  args.finish();
  if (man)
    std::fputs(manPage(*man).c_str(), stdout);
  else if (manPages)
    for (const auto& name : manPageNames()) std::printf("%s\n", name.c_str());
  else if (completion)
    std::fputs(bashCompletion().c_str(), stdout);
  else if (markdown)
    std::fputs(markdownTables().c_str(), stdout);
  else
    printUsage();
  return 0;
}

int runCli(int argc, char** argv) {
  setLogSink([](LogLevel level, const std::string& msg) {
    if (level == LogLevel::Debug) return;
    const char* tag = level == LogLevel::Warning ? "warning: " : level == LogLevel::Error ? "error: " : "";
    std::cerr << tag << msg << "\n";
  });
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    printUsage();
    return argc < 2 ? 1 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("dtfabric %s\n", DTF_VERSION);
    return 0;
  }
  std::string name = argv[1];
  CommandArgs rest(argv + 2, argv + argc);
  for (const auto& c : commands()) {
    if (name != c.name) continue;
    try {
      return c.run(rest);
    } catch (const UsageError& e) {
      std::cerr << "dtfabric " << name << ": " << e.what() << "\n(see `dtfabric " << name << " --help`)\n";
      return 1;
    } catch (const GlError& e) {
      std::cerr << "dtfabric " << name << ": GL error: " << e.what() << "\n";
      return 3;
    } catch (const Error& e) {
      std::cerr << "dtfabric " << name << ": " << e.what() << "\n";
      return 2;
    } catch (const std::bad_alloc&) {
      std::cerr << "dtfabric " << name << ": out of memory\n";
      return 2;
    } catch (const std::exception& e) {
      if (const std::string fs = filesystemErrorMessage(e); !fs.empty()) {
        std::cerr << "dtfabric " << name << ": " << fs << "\n";
        return 2;
      }
      std::cerr << "dtfabric " << name << ": unexpected error: " << e.what() << "\n";
      return 2;
    }
  }
  std::cerr << "dtfabric: unknown command '" << name << "'\n";
  printUsage();
  return 1;
}

} // namespace dtf::app
