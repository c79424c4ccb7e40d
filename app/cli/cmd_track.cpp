// `dtfabric track`: deterministic tensor tractography (surfaces/tracking.h) to any tract file format.
#include "app/cli/args.h"
#include "app/cli/commands.h"
#include "app/scene/surface_spec.h"
#include "app/scene/tensor_input.h"
#include "app/scene/track_job.h"
#include "app/scene/tract_files.h"
#include "io/atomic_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/slices.h"
#include "surfaces/tracking.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace dtf::app {

namespace {
const char* kHelp = R"(usage: dtfabric track INPUT -o OUT.tck|.trk|.trk.gz|.trx|.vtk|.vtp [SEEDS] [OPTIONS]

Deterministic tensor tractography: streamlines along the principal eigenvector of the trilinearly
interpolated tensor, in both directions from each seed, written in world RAS mm (.trk/.trx on INPUT's grid).
INPUT is a tensor volume or a DWI (with --bval/--bvec or sibling .bval/.bvec files).

Seeds (one of; default: random points in the voxels where INPUT holds a tensor)
  --seeds-mask M        random points in the non-zero voxels of the NIfTI mask M
  --seed-sphere X,Y,Z,R random points in a ball (world mm)
  --seed-surface SPEC   random points on a surface: fa=T | slice=AXIS[:I] | plane=... | mesh=FILE | ...
  --seed-slice AXIS:I   random points in the valid voxels of axial|coronal|sagittal slice I
How many (one of; default --select 1000)
  --select N            keep seeding until N streamlines are accepted (at most 1000 x N seeds)
  --seeds N             track exactly N seeds and keep the streamlines that pass
  --seeds-per-voxel K   with --seeds-mask: K seeds in every mask voxel
Tracking
  --step MM             step length (default 1)
  --fa-stop F           stop where FA < F; seeds below F are rejected (default 0.15)
  --angle DEG           largest turn between successive steps (default 60, per step as in MRtrix)
  --min-length MM       discard shorter streamlines (default 30)
  --max-length MM       stop at this length (default 250)
  --rk4 | --euler       integrator (default RK4; MRtrix Tensor_Det uses Euler)
  --mask M              stop where the NIfTI mask M is zero
  --seed S              random seed (default 1); the output depends only on it, not on --threads
  --threads T           worker threads (default: all cores)
Other
  --layout L            tensor layout override (fsl, mrtrix, symmatrix, dtitk)
  --bval F --bvec F     treat INPUT as a DWI and fit tensors
  --force               overwrite an existing output
  --json                print the report as one JSON object
)";

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
} // namespace

int cmdTrack(const CommandArgs& argv) {
  Args args(argv, {"json", "force", "help", "rk4", "euler"});
  if (args.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::string input = args.positional(0, "INPUT");
  const std::string output = args.getOr("output", "");
  if (output.empty()) throw UsageError("missing -o OUT.tck|.trk|.trk.gz|.trx|.vtk|.vtp");
  if (!isTractFileName(output))
    throw UsageError("output " + output + " must end in .tck, .trk, .trk.gz, .trx, .vtk or .vtp");
  auto seedsMask = args.get("seeds-mask"), seedSphere = args.get("seed-sphere"),
       seedSurface = args.get("seed-surface"), seedSlice = args.get("seed-slice");
  const int seedKinds = !!seedsMask + !!seedSphere + !!seedSurface + !!seedSlice;
  if (seedKinds > 1)
    throw UsageError("give at most one of --seeds-mask, --seed-sphere, --seed-surface, --seed-slice");
  auto select = args.get("select"), seedsN = args.get("seeds");
  if (select && seedsN) throw UsageError("give either --select or --seeds, not both");
  const int selectN = args.getInt("select", 1000), seedCount = args.getInt("seeds", 0);
  const int perVoxel = args.getInt("seeds-per-voxel", 0);
  if (perVoxel < 0 || (perVoxel > 0 && !seedsMask))
    throw UsageError("--seeds-per-voxel K needs --seeds-mask and K >= 0");
  if (select && selectN <= 0) throw UsageError("--select must be positive");
  if (seedsN && seedCount <= 0) throw UsageError("--seeds must be positive");

  surfaces::TrackingOptions to;
  to.stepMm = args.getDouble("step", to.stepMm);
  to.faStop = args.getDouble("fa-stop", to.faStop);
  to.maxAngleDeg = args.getDouble("angle", to.maxAngleDeg);
  to.minLengthMm = args.getDouble("min-length", to.minLengthMm);
  to.maxLengthMm = args.getDouble("max-length", to.maxLengthMm);
  const bool rk4 = args.flag("rk4"), euler = args.flag("euler");
  if (rk4 && euler) throw UsageError("give either --rk4 or --euler");
  to.rk4 = !euler;
  const int rngSeed = args.getInt("seed", 1);
  to.threads = args.getInt("threads", 0);
  if (to.threads < 0) throw UsageError("--threads must be >= 0");
  const std::string stopMask = args.getOr("mask", "");
  TensorInputOptions in;
  in.layout = io::parseLayout(args.getOr("layout", "auto"));
  in.bval = args.getOr("bval", "");
  in.bvec = args.getOr("bvec", "");
  const bool json = args.flag("json"), force = args.flag("force");
  args.finish();
  surfaces::validate(to);

  std::string surfaceFile;
  SurfaceSpec surfaceSpec;
  if (seedSurface) {
    surfaceSpec = parseSurfaceSpec(*seedSurface);
    surfaceFile = surfaceSpec.file;
  }
  io::refuseOverwritingInput(output,
                             {input, in.bval, in.bvec, stopMask, seedsMask.value_or(""), surfaceFile});
  if (!force && std::filesystem::exists(output))
    throw InputError(output + " exists (use --force to overwrite)");

  TrackRequest request;
  request.input = input;
  request.tensorOptions = in;
  request.tensorOptions.quiet = json;
  request.seedsMask = seedsMask.value_or("");
  if (seedSphere) {
    auto v = parseList(*seedSphere, 4, "--seed-sphere");
    request.seedSphere = glm::dvec4(v[0], v[1], v[2], v[3]);
  }
  if (seedSurface) request.seedSurface = surfaceSpec;
  if (seedSlice) {
    auto colon = seedSlice->find(':');
    if (colon == std::string::npos) throw UsageError("--seed-slice expects AXIS:INDEX, e.g. axial:20");
    int index = 0;
    try {
      std::size_t used = 0;
      index = std::stoi(seedSlice->substr(colon + 1), &used);
      if (used != seedSlice->size() - colon - 1) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw UsageError("--seed-slice index '" + seedSlice->substr(colon + 1) + "' is not an integer");
    }
    request.seedSliceAxis = seedSlice->substr(0, colon);
    request.seedSliceIndex = index;
  }
  request.select = selectN;
  request.seedCount = seedsN ? seedCount : 0;
  request.seedsPerVoxel = perVoxel;
  request.rngSeed = static_cast<std::uint64_t>(rngSeed);
  request.stopMask = stopMask;
  const bool interactive = !json && ::isatty(2);
  if (interactive)
    to.progress = [](std::size_t done, std::size_t planned) {
      std::fprintf(stderr, "\rtracking: %zu / %zu seeds", done, planned);
      std::fflush(stderr);
    };
  request.options = to;
  TrackRun run = runTrack(request);
  const surfaces::TrackingResult& r = run.result;
  const std::string& mode = run.mode;
  const double seconds = run.seconds;
  if (interactive) std::fputs("\n", stderr);
  if (r.lines.lineCount() == 0) {
    std::ostringstream msg;
    msg << "no streamline passed from " << r.seedsTried << " seeds (" << r.seedsBelowFa << " below FA "
        << to.faStop << " or outside the data, " << r.tooShort << " shorter than " << to.minLengthMm
        << " mm)";
    throw InputError(msg.str());
  }
  if (!seedsN && perVoxel == 0 && r.lines.lineCount() < static_cast<std::size_t>(selectN))
    logWarning("only " + std::to_string(r.lines.lineCount()) + " of " + std::to_string(selectN) +
               " streamlines after " + std::to_string(r.seedsTried) + " seeds");
  writeTracts(output, r.lines, &run.grid);

  std::vector<double> lengths(r.lines.lineCount());
  for (std::size_t i = 0; i < lengths.size(); ++i)
    lengths[i] = lineLength(r.lines, i);
  std::sort(lengths.begin(), lengths.end());
  const double medLen = lengths[lengths.size() / 2];
  if (json) {
    std::printf(
        "{\"output\": \"%s\", \"streamlines\": %zu, \"points\": %zu, \"seeds_tried\": %zu, "
        "\"seeds_below_fa\": %zu, \"too_short\": %zu, \"length_min_mm\": %.3f, \"length_median_mm\": %.3f, "
        "\"length_max_mm\": %.3f, \"seconds\": %.4f, \"threads\": %d, \"integrator\": \"%s\", "
        "\"step_mm\": %g, \"fa_stop\": %g, \"angle_deg\": %g, \"seed\": %d, \"cancelled\": %s}\n",
        output.c_str(), r.lines.lineCount(), r.lines.points.size(), r.seedsTried, r.seedsBelowFa, r.tooShort,
        lengths.front(), medLen, lengths.back(), seconds, r.threads, to.rk4 ? "rk4" : "euler", to.stepMm,
        to.faStop, to.maxAngleDeg, rngSeed, r.cancelled ? "true" : "false");
  } else {
    std::printf("seeds: %s (%s)\n", run.seedDescription.c_str(), mode.c_str());
    std::printf("tracking: %s, step %g mm, FA stop %g, angle %g deg/step, length %g..%g mm%s\n",
                to.rk4 ? "RK4" : "Euler", to.stepMm, to.faStop, to.maxAngleDeg, to.minLengthMm,
                to.maxLengthMm, stopMask.empty() ? "" : (", stop mask " + stopMask).c_str());
    std::printf("wrote %zu streamlines (%zu points; length %.1f / %.1f / %.1f mm min/median/max) to %s\n",
                r.lines.lineCount(), r.lines.points.size(), lengths.front(), medLen, lengths.back(),
                output.c_str());
    std::printf("from %zu seeds (%zu below FA or outside the data, %zu too short) in %.2f s on %d threads\n",
                r.seedsTried, r.seedsBelowFa, r.tooShort, seconds, r.threads);
  }
  return 0;
}

} // namespace dtf::app
