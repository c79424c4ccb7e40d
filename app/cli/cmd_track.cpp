// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric track`: deterministic tensor tractography (surfaces/tracking/tracking.h) to any tract file
// format.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/slices.h"
#include "surfaces/tracking/tracking.h"
#include "surfaces/tracking/tracking_parameters.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/track_job.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

namespace dtf::app {

namespace {

std::vector<CliOption> seedingRows(const session::TrackRequest& d) {
  using O = CliOption;
  return {
      O::text("output", "OUT.tck|.trk|.trk.gz|.trx|.vtk|.vtp", "the tract file to write")
          .required()
          .under("Output"),
      O::text("seeds-mask", "M", "random points in the non-zero voxels of the NIfTI mask M")
          .hidden()
          .under("Seeds (one of; default: random points in the voxels where INPUT holds a tensor)"),
      O::text("seed-sphere", "X,Y,Z,R", "random points in a ball (world mm)").hidden(),
      O::text("seed-surface", "SPEC",
              "random points on a surface: fa=T | slice=AXIS[:I] | plane=... | mesh=FILE | ...")
          .hidden(),
      O::text("seed-slice", "AXIS:I", "random points in the valid voxels of axial|coronal|sagittal slice I")
          .hidden(),
      O::integer("select", "N", d.number, aboveUpTo(0, session::kMaxSelect),
                 "keep seeding until N streamlines are accepted (at most 1000 x N seeds)")
          .hidden()
          .under("How many (one of; default --select " + std::to_string(d.number) + ")"),
      O::integer("seeds", "N", 0, aboveUpTo(0, session::kMaxSeeds),
                 "track exactly N seeds and keep the streamlines that pass")
          .noDefault()
          .hidden(),
      O::integer("seeds-per-voxel", "K", 0, closedRange(0, session::kMaxSeedsPerVoxel),
                 "with --seeds-mask: K seeds in every mask voxel")
          .hidden(),
  };
}

// The tracking parameters' rows from their table (surfaces/tracking/tracking_parameters.h).
std::vector<CliOption> parameterRows(const surfaces::TrackingParams& d) {
  std::vector<CliOption> rows;
  for (const auto& p : surfaces::trackingParameters()) {
    CliOption o = CliOption::number(p.name, p.metavar, p.get(d), p.range, p.help);
    o.unit = p.unit;
    rows.push_back(std::move(o).hidden());
  }
  rows.front().group = "Tracking";
  return rows;
}

std::vector<CliOption> trackingRows(const session::TrackRequest& d) {
  using O = CliOption;
  const surfaces::TrackingOptions& to = d.options;
  std::vector<CliOption> rows = parameterRows(to);
  std::vector<CliOption> more = {
      O::flag("rk4", surfaces::kRk4Help).hidden(),
      O::flag("euler", surfaces::kEulerHelp).hidden(),
      O::text("mask", "M", "stop where the NIfTI mask M is zero").hidden(),
      O::integer("seed", "S", static_cast<int>(d.rngSeed), anyNumber(),
                 "random seed; the output depends only on it, not on --threads")
          .hidden(),
      O::integer("threads", "T", to.threads, atLeast(0), "worker threads").defaultSays("all cores").hidden(),
      layoutOption(LayoutNames::Tensor).hidden().under("Other"),
      bvalOption().hidden(),
      bvecOption().hidden(),
      O::flag("force", "overwrite an existing output").hidden(),
      O::flag("json", "print the report as one JSON object").hidden(),
  };
  rows.insert(rows.end(), more.begin(), more.end());
  return rows;
}

} // namespace

const OptionTable& trackOptions() {
  static const OptionTable table = [] {
    const session::TrackRequest d; // the defaults
    OptionTable t;
    t.command = "track";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.synopsisTail = "[SEEDS] [OPTIONS]";
    t.intro =
        "Deterministic tensor tractography: streamlines along the principal eigenvector of the trilinearly\n"
        "interpolated tensor, in both directions from each seed, written in world RAS mm (.trk/.trx on "
        "INPUT's grid).\n"
        "INPUT is a tensor volume or a DWI (with --bval/--bvec or sibling .bval/.bvec files).";
    t.options = seedingRows(d);
    const std::vector<CliOption> tracking = trackingRows(d);
    t.options.insert(t.options.end(), tracking.begin(), tracking.end());
    // Targeted tracking: the same region rows as `select`, applied to each streamline as it is tracked.
    std::vector<CliOption> regions = regionOptions();
    for (auto& o : regions)
      o = std::move(o).hidden();
    regions.front().group = "Targeted tracking (keep only streamlines that pass these regions, as `select`)";
    t.options.insert(t.options.end(), regions.begin(), regions.end());
    return t;
  }();
  return table;
}

namespace {

std::vector<double> parseList(const std::string& text, std::size_t n, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    char* end = nullptr;
    double d = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(d))
      throw UsageError(what + ": '" + part + "' is not a number");
    v.push_back(d);
  }
  if (v.size() != n) throw UsageError(what + " expects " + std::to_string(n) + " comma-separated numbers");
  return v;
}

double lineLength(const Polylines& l, std::size_t i) {
  double s = 0;
  for (std::uint32_t p = l.offsets[i] + 1; p < l.offsets[i + 1]; ++p)
    s += glm::length(l.points[p] - l.points[p - 1]);
  return s;
}

// The command line of one track run: the request, and what is checked or parsed after the output check.
struct TrackCli {
  session::TrackRequest request;
  std::string output;
  std::optional<std::string> seedSphere, seedSurface, seedSlice;
  bool seedsGiven = false; // --seeds N: no shortfall warning
  bool json = false, force = false;
};

// Where and how many seeds: at most one place, at most one count.
void readSeeding(ParsedOptions& args, TrackCli& cli) {
  session::TrackRequest& r = cli.request;
  const auto seedsMask = args.get("seeds-mask");
  cli.seedSphere = args.get("seed-sphere");
  cli.seedSurface = args.get("seed-surface");
  cli.seedSlice = args.get("seed-slice");
  if (!!seedsMask + !!cli.seedSphere + !!cli.seedSurface + !!cli.seedSlice > 1)
    throw UsageError("give at most one of --seeds-mask, --seed-sphere, --seed-surface, --seed-slice");
  using K = session::SeedKind;
  r.seeds = seedsMask         ? K::Mask
            : cli.seedSphere  ? K::Sphere
            : cli.seedSurface ? K::Surface
            : cli.seedSlice   ? K::Slice
                              : K::Data;
  r.seedsMask = seedsMask.value_or("");
  cli.seedsGiven = args.given("seeds");
  if (args.given("select") && cli.seedsGiven) throw UsageError("give either --select or --seeds, not both");
  const int perVoxel = args.integer("seeds-per-voxel");
  if (perVoxel > 0 && !seedsMask) throw UsageError("--seeds-per-voxel K needs --seeds-mask and K >= 0");
  using C = session::SeedCount;
  r.count = perVoxel > 0 ? C::PerVoxel : cli.seedsGiven ? C::Seeds : C::Select;
  const int select = args.integer("select"), seeds = cli.seedsGiven ? args.integer("seeds") : 0;
  r.number = perVoxel > 0 ? perVoxel : cli.seedsGiven ? seeds : select;
}

void readTracking(ParsedOptions& args, TrackCli& cli) {
  session::TrackRequest& r = cli.request;
  surfaces::TrackingOptions& to = r.options;
  for (const auto& p : surfaces::trackingParameters())
    p.set(to, args.number(p.name));
  const bool rk4 = args.flag("rk4"), euler = args.flag("euler");
  if (rk4 && euler) throw UsageError("give either --rk4 or --euler");
  to.rk4 = !euler;
  r.rngSeed = static_cast<std::uint64_t>(args.integer("seed"));
  to.threads = args.integer("threads");
  r.stopMask = args.text("mask");
  r.tensorOptions.layout = io::parseLayout(args.text("layout"));
  r.tensorOptions.bval = args.text("bval");
  r.tensorOptions.bvec = args.text("bvec");
}

// The seed sphere and seed slice, parsed after the output check.
void parseSeedPlaces(TrackCli& cli) {
  session::TrackRequest& r = cli.request;
  if (cli.seedSphere) {
    auto v = parseList(*cli.seedSphere, 4, "--seed-sphere");
    r.centre = glm::dvec3(v[0], v[1], v[2]);
    r.radiusMm = v[3];
  }
  if (!cli.seedSlice) return;
  const std::string& slice = *cli.seedSlice;
  auto colon = slice.find(':');
  if (colon == std::string::npos) throw UsageError("--seed-slice expects AXIS:INDEX, e.g. axial:20");
  try {
    std::size_t used = 0;
    r.sliceIndex = std::stoi(slice.substr(colon + 1), &used);
    if (used != slice.size() - colon - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw UsageError("--seed-slice index '" + slice.substr(colon + 1) + "' is not an integer");
  }
  r.sliceAxis = static_cast<int>(surfaces::parseSliceAxis(slice.substr(0, colon)));
}

// Tracks, with a progress line on an interactive terminal.
session::TrackRun track(session::TrackRequest& request, bool json) {
  const bool interactive = !json && ::isatty(2);
  if (interactive)
    request.options.progress = [](std::size_t done, std::size_t planned) {
      std::fprintf(stderr, "\rtracking: %zu / %zu seeds", done, planned);
      std::fflush(stderr);
    };
  session::TrackRun run = session::runTrack(request);
  if (interactive) std::fputs("\n", stderr);
  return run;
}

// No streamline is an input error; fewer than selected a warning.
void checkResult(const TrackCli& cli, const surfaces::TrackingResult& r) {
  const session::TrackRequest& q = cli.request;
  if (r.lines.lineCount() == 0) {
    std::ostringstream msg;
    msg << "no streamline passed from " << r.seedsTried << " seeds (" << r.seedsBelowFa << " below FA "
        << q.options.faStop << " or outside the data, " << r.tooShort << " shorter than "
        << q.options.minLengthMm << " mm"
        << (q.regions.hasRegions() ? ", " + std::to_string(r.rejectedByRegions) + " outside the regions" : "")
        << ")";
    throw InputError(msg.str());
  }
  if (q.count == session::SeedCount::Select && r.lines.lineCount() < static_cast<std::size_t>(q.number))
    logWarning("only " + std::to_string(r.lines.lineCount()) + " of " + std::to_string(q.number) +
               " streamlines after " + std::to_string(r.seedsTried) + " seeds");
}

void printReport(const TrackCli& cli, const session::TrackRun& run) {
  const surfaces::TrackingResult& r = run.result;
  const surfaces::TrackingOptions& to = cli.request.options;
  const char* output = cli.output.c_str();
  std::vector<double> lengths(r.lines.lineCount());
  for (std::size_t i = 0; i < lengths.size(); ++i)
    lengths[i] = lineLength(r.lines, i);
  std::sort(lengths.begin(), lengths.end());
  const double medLen = lengths[lengths.size() / 2];
  if (cli.json) {
    const nlohmann::ordered_json j = {{"output", cli.output},
                                      {"streamlines", r.lines.lineCount()},
                                      {"points", r.lines.points.size()},
                                      {"seeds_tried", r.seedsTried},
                                      {"seeds_below_fa", r.seedsBelowFa},
                                      {"too_short", r.tooShort},
                                      {"rejected_by_regions", r.rejectedByRegions},
                                      {"length_min_mm", lengths.front()},
                                      {"length_median_mm", medLen},
                                      {"length_max_mm", lengths.back()},
                                      {"seconds", run.seconds},
                                      {"threads", r.threads},
                                      {"integrator", to.rk4 ? "rk4" : "euler"},
                                      {"step_mm", to.stepMm},
                                      {"fa_stop", to.faStop},
                                      {"angle_deg", to.maxAngleDeg},
                                      {"seed", static_cast<int>(cli.request.rngSeed)},
                                      {"cancelled", r.cancelled}};
    std::printf("%s\n", io::jsonText(j).c_str());
    return;
  }
  const std::string& stopMask = cli.request.stopMask;
  std::printf("seeds: %s (%s)\n", run.seedDescription.c_str(), run.mode.c_str());
  std::printf("tracking: %s, step %g mm, FA stop %g, angle %g deg/step, length %g..%g mm%s\n",
              to.rk4 ? "RK4" : "Euler", to.stepMm, to.faStop, to.maxAngleDeg, to.minLengthMm, to.maxLengthMm,
              stopMask.empty() ? "" : (", stop mask " + stopMask).c_str());
  std::printf("wrote %zu streamlines (%zu points; length %.1f / %.1f / %.1f mm min/median/max) to %s\n",
              r.lines.lineCount(), r.lines.points.size(), lengths.front(), medLen, lengths.back(), output);
  std::printf("from %zu seeds (%zu below FA or outside the data, %zu too short%s) in %.2f s on %d threads\n",
              r.seedsTried, r.seedsBelowFa, r.tooShort,
              cli.request.regions.hasRegions()
                  ? (", " + std::to_string(r.rejectedByRegions) + " outside the regions").c_str()
                  : "",
              run.seconds, r.threads);
}

} // namespace

int cmdTrack(const CommandArgs& argv) {
  ParsedOptions args(trackOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  TrackCli cli;
  session::TrackRequest& request = cli.request;
  request.input = args.positional(0, "INPUT");
  cli.output = args.required("output");
  if (!session::isTractFileName(cli.output))
    throw UsageError("output " + cli.output + " must end in .tck, .trk, .trk.gz, .trx, .vtk or .vtp");
  readSeeding(args, cli);
  readTracking(args, cli);
  request.regions.regions = regionsFrom(args);
  cli.json = args.flag("json");
  cli.force = args.flag("force");
  args.finish();
  surfaces::validate(request.options);

  if (cli.seedSurface) request.seedSurface = session::parseSurfaceSpec(*cli.seedSurface);
  io::refuseOverwritingInput(cli.output, {request.input, request.tensorOptions.bval,
                                          request.tensorOptions.bvec, request.stopMask, request.seedsMask,
                                          request.seedSurface ? request.seedSurface->file : ""});
  if (!cli.force && io::outputExists(cli.output))
    throw InputError(cli.output + " exists (use --force to overwrite)");
  parseSeedPlaces(cli);
  request.tensorOptions.quiet = cli.json;

  session::TrackRun run = track(request, cli.json);
  checkResult(cli, run.result);
  session::writeTracts(cli.output, run.result.lines, &run.grid);
  printReport(cli, run);
  return 0;
}

} // namespace dtf::app
