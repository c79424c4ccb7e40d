// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench tracts`: throughput of deterministic tensor tracking on the real brain with the settings
// of the reference tracks (MRtrix tckgen -algorithm Tensor_Det: seeds and mask from mask.nii.gz, step 1 mm,
// FA cutoff 0.15, 60 deg, min length 30 mm). When MRtrix's tckgen is on the PATH (Debian package mrtrix3)
// it runs in the same invocation with the same settings and threads on the raw DWI, as the peer. tckgen
// interpolates the DWI and fits a tensor at every step; we interpolate the fitted tensors, as the fabric does.
#include "app/bench/bench.h"
#include "io/formats/process.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "surfaces/tracking/tracking.h"
#include "io/formats/json.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <nlohmann/json.hpp>
#include <sstream>
#include <sys/resource.h>
#include <thread>
#include <unistd.h>

namespace {
struct PeerRun {
  bool ran = false;
  double seconds = 0, cpuSeconds = 0;
  std::string note;
};

} // namespace

namespace dtf::app {

const OptionTable& benchTractsOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench tracts";
    t.intro =
        "Times selecting N deterministic tensor streamlines on the real brain\n"
        "(iu_prisma_dwi/derived/dti_tensor.nii.gz, seeds and stop mask from mask.nii.gz, step 1 mm, FA 0.15,\n"
        "60 deg, length 30..250 mm, RK4 unless --euler) on all cores. Peer, when on the PATH: MRtrix\n"
        "tckgen -algorithm Tensor_Det with the same settings (Debian package mrtrix3).";
    t.options = {
        O::integer("count", "N", 100000, closedRange(1, 100000000), "streamlines to select"),
        O::integer("threads", "T", 0, atLeast(0), "tracking threads, 0 = all cores"),
        O::flag("euler", "Euler steps instead of RK4"),
        O::integer("repeat", "R", 1, closedRange(1, 1000), "runs, the median is reported"),
        O::flag("json", "one JSON object"),
        sharedDataOption(),
    };
    return t;
  }();
  return table;
}

namespace {

using Clock = std::chrono::steady_clock;

// The real brain's tensors and mask, with their load time.
struct TrackingInput {
  io::LoadedTensors loaded;
  MaskVolume mask;
  double loadSeconds = 0;
};

TrackingInput loadTrackingInput(const std::filesystem::path& dir) {
  TrackingInput in;
  const auto t0 = Clock::now();
  in.loaded = io::readTensorVolume((dir / "dti_tensor.nii.gz").string());
  ScalarVolume m = io::readScalarVolume((dir / "mask.nii.gz").string());
  in.mask = MaskVolume(m.grid, 1);
  for (std::size_t i = 0; i < m.grid.voxelCount(); ++i)
    in.mask.data[i] = m.data[i] > 0 ? 1 : 0;
  in.loadSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return in;
}

// The reference tracks' settings (tckgen's defaults as used for them).
surfaces::TrackingOptions referenceSettings(const MaskVolume& mask, bool euler, int threads) {
  surfaces::TrackingOptions o;
  o.stepMm = 1.0;
  o.faStop = 0.15;
  o.maxAngleDeg = 60;
  o.minLengthMm = 30;
  o.maxLengthMm = 250;
  o.rk4 = !euler;
  o.mask = &mask;
  o.threads = threads;
  return o;
}

struct TrackingTimes {
  surfaces::TrackingResult result;
  double seconds = 0, cpuSeconds = 0; // medians over the repeats
};

TrackingTimes timeTracking(const TrackingInput& in, const surfaces::TrackingOptions& o, int count, int repeat) {
  const surfaces::SeedSource seeds = surfaces::seedsFromMask(in.mask, 0, 20240601);
  std::vector<double> times, cpu;
  TrackingTimes t;
  for (int i = 0; i < repeat; ++i) {
    auto t1 = Clock::now();
    const std::clock_t c1 = std::clock(); // process CPU time, all threads: shows when other load steals cores
    t.result = surfaces::trackSelect(in.loaded.field, seeds, static_cast<std::size_t>(count), o);
    times.push_back(std::chrono::duration<double>(Clock::now() - t1).count());
    cpu.push_back(static_cast<double>(std::clock() - c1) / CLOCKS_PER_SEC);
  }
  t.seconds = median(times);
  t.cpuSeconds = median(cpu);
  return t;
}

// MRtrix tckgen on the raw DWI with the same settings and threads, when it is on the PATH.
PeerRun runTckgen(const std::filesystem::path& data, int count, int threads) {
  PeerRun peer;
  const std::string tckgen = dtf::io::findOnPath("tckgen");
  const auto raw = data / "iu_prisma_dwi";
  const auto mask = (raw / "derived" / "mask.nii.gz").string();
  if (tckgen.empty()) {
    peer.note = "MRtrix tckgen is not on the PATH (Debian package mrtrix3); no comparison";
    return peer;
  }
  if (!std::filesystem::exists(raw / "dwi.nii.gz")) {
    peer.note = "the raw DWI for tckgen is missing";
    return peer;
  }
  const auto out =
      std::filesystem::temp_directory_path() / ("dtf_bench_tckgen_" + std::to_string(::getpid()) + ".tck");
  const double c0 = childCpuSeconds();
  auto t0 = Clock::now();
  const int rc = dtf::io::runProgram(
      {tckgen, (raw / "dwi.nii.gz").string(), out.string(), "-algorithm", "Tensor_Det", "-fslgrad",
       (raw / "dwi.bvec").string(), (raw / "dwi.bval").string(), "-seed_image", mask, "-mask", mask, "-select",
       std::to_string(count), "-step", "1", "-cutoff", "0.15", "-angle", "60", "-minlength", "30", "-maxlength",
       "250", "-nthreads", std::to_string(threads), "-quiet", "-force"});
  peer.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  peer.cpuSeconds = childCpuSeconds() - c0;
  std::error_code ec;
  std::filesystem::remove(out, ec);
  peer.ran = rc == 0;
  if (!peer.ran) peer.note = "tckgen failed (exit status " + std::to_string(rc) + ")";
  return peer;
}

void printTractsJson(const TrackingTimes& t, const TrackingInput& in, bool rk4, const PeerRun& peer) {
  const surfaces::TrackingResult& r = t.result;
  const double s = t.seconds;
  const nlohmann::ordered_json j = {{"streamlines", r.lines.lineCount()},
                                    {"points", r.lines.points.size()},
                                    {"seeds", r.seedsTried},
                                    {"seconds", s},
                                    {"streamlines_per_s", static_cast<double>(r.lines.lineCount()) / s},
                                    {"points_per_s", static_cast<double>(r.lines.points.size()) / s},
                                    {"seeds_per_s", static_cast<double>(r.seedsTried) / s},
                                    {"cpu_s", t.cpuSeconds},
                                    {"threads", r.threads},
                                    {"hardware_threads", std::thread::hardware_concurrency()},
                                    {"integrator", rk4 ? "rk4" : "euler"},
                                    {"load_s", in.loadSeconds},
                                    {"peer", "MRtrix tckgen -algorithm Tensor_Det"},
                                    {"peer_ran", peer.ran},
                                    {"peer_seconds", peer.seconds},
                                    {"peer_cpu_s", peer.cpuSeconds}};
  std::printf("%s\n", io::jsonText(j).c_str());
}

void printTractsTable(const TrackingTimes& t, const TrackingInput& in, bool rk4, int repeat, const PeerRun& peer) {
  const surfaces::TrackingResult& r = t.result;
  const double s = t.seconds, cpuS = t.cpuSeconds;
  std::printf("deterministic tensor tracking on the real brain (72x72x39, 3 mm), %s, step 1 mm, FA 0.15, 60 deg, "
              "30..250 mm\n",
              rk4 ? "RK4" : "Euler");
  std::printf("  loading tensor + mask: %.2f s\n", in.loadSeconds);
  std::printf("  %zu streamlines (%zu points) from %zu seeds in %.2f s on %d threads%s\n", r.lines.lineCount(),
              r.lines.points.size(), r.seedsTried, s, r.threads, repeat > 1 ? " (median of repeats)" : "");
  std::printf("  CPU time %.2f s over all threads (%.0f%% of %d threads busy)\n", cpuS, 100 * cpuS / (s * r.threads),
              r.threads);
  std::printf("  %.0f streamlines/s, %.0f seeds/s, %.2f M points/s\n", static_cast<double>(r.lines.lineCount()) / s,
              static_cast<double>(r.seedsTried) / s, static_cast<double>(r.lines.points.size()) / s / 1e6);
  if (peer.ran)
    std::printf("  peer: MRtrix tckgen -algorithm Tensor_Det, same settings and %d threads: %.2f s wall, %.2f s CPU"
                " -> dtfabric %.2fx faster (wall), %.2fx (CPU)\n",
                r.threads, peer.seconds, peer.cpuSeconds, peer.seconds / s, peer.cpuSeconds / std::max(cpuS, 1e-9));
  else
    std::printf("  peer: %s\n", peer.note.c_str());
}

} // namespace

int benchTracts(const CommandArgs& argv) {
  ParsedOptions args(benchTractsOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const int count = args.integer("count");
  const int threads = args.integer("threads");
  const int repeat = args.integer("repeat");
  const bool json = args.flag("json"), euler = args.flag("euler");
  auto dataArg = args.get("data");
  args.finish();
  auto data = findSharedDataDir(dataArg);
  if (!data || !std::filesystem::exists(*data / "iu_prisma_dwi/derived/dti_tensor.nii.gz"))
    throw InputError(
        "bench tracts needs the shared data (iu_prisma_dwi/derived); set DTF_SHARED_DATA or --data");

  const TrackingInput in = loadTrackingInput(*data / "iu_prisma_dwi/derived");
  const surfaces::TrackingOptions o = referenceSettings(in.mask, euler, threads);
  const TrackingTimes t = timeTracking(in, o, count, repeat);
  const PeerRun peer = runTckgen(*data, count, t.result.threads);
  if (json)
    printTractsJson(t, in, o.rk4, peer);
  else
    printTractsTable(t, in, o.rk4, repeat, peer);
  return 0;
}

} // namespace dtf::app
