// `dtfabric bench tracts`: throughput of deterministic tensor tracking on the real brain with the settings
// of the reference tracks (MRtrix tckgen -algorithm Tensor_Det: seeds and mask from mask.nii.gz, step 1 mm,
// FA cutoff 0.15, 60 deg, min length 30 mm). When MRtrix's tckgen is on the PATH (Debian package mrtrix3)
// it runs in the same invocation with the same settings and threads on the raw DWI, as the peer. tckgen
// interpolates the DWI and fits a tensor at every step; we interpolate the fitted tensors, as the fabric does.
#include "app/bench/bench.h"
#include "app/cli/options.h"
#include "app/cli/args.h"
#include "io/model/error.h"
#include "io/tensor_io.h"
#include "surfaces/tracking.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <sys/resource.h>
#include <thread>
#include <unistd.h>

namespace {
// The tckgen executable on the PATH, or empty.
std::string findTckgen() {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':'))
    if (!dir.empty() && ::access((dir + "/tckgen").c_str(), X_OK) == 0) return dir + "/tckgen";
  return {};
}

struct PeerRun {
  bool ran = false;
  double seconds = 0, cpuSeconds = 0;
  std::string note;
};

double childCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
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

int benchTracts(const CommandArgs& argv) {
  ParsedOptions args(benchTractsOptions(), argv);
  if (args.helpRequested()) {
    std::fputs(benchTractsOptions().help().c_str(), stdout);
    return 0;
  }
  const int count = args.integer("count");
  const int threads = args.integer("threads");
  const int repeat = args.integer("repeat");
  const bool json = args.flag("json"), euler = args.flag("euler");
  auto dataArg = args.get("data");
  args.finish();
  if (count <= 0) throw UsageError("--count must be positive");
  auto data = findSharedDataDir(dataArg);
  if (!data || !std::filesystem::exists(*data / "iu_prisma_dwi/derived/dti_tensor.nii.gz"))
    throw InputError(
        "bench tracts needs the shared data (iu_prisma_dwi/derived); set DTF_SHARED_DATA or --data");
  const auto dir = *data / "iu_prisma_dwi/derived";

  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  io::LoadedTensors loaded = io::readTensorVolume((dir / "dti_tensor.nii.gz").string());
  ScalarVolume m = io::readScalarVolume((dir / "mask.nii.gz").string());
  MaskVolume mask(m.grid, 1);
  for (std::size_t i = 0; i < m.grid.voxelCount(); ++i)
    mask.data[i] = m.data[i] > 0 ? 1 : 0;
  const double loadS = std::chrono::duration<double>(Clock::now() - t0).count();

  surfaces::TrackingOptions o;
  o.stepMm = 1.0;
  o.faStop = 0.15;
  o.maxAngleDeg = 60;
  o.minLengthMm = 30;
  o.maxLengthMm = 250;
  o.rk4 = !euler;
  o.mask = &mask;
  o.threads = threads;
  const surfaces::SeedSource seeds = surfaces::seedsFromMask(mask, 0, 20240601);
  std::vector<double> times, cpu;
  surfaces::TrackingResult r;
  for (int i = 0; i < repeat; ++i) {
    auto t1 = Clock::now();
    const std::clock_t c1 = std::clock(); // process CPU time, all threads: shows when other load steals cores
    r = surfaces::trackSelect(loaded.field, seeds, static_cast<std::size_t>(count), o);
    times.push_back(std::chrono::duration<double>(Clock::now() - t1).count());
    cpu.push_back(static_cast<double>(std::clock() - c1) / CLOCKS_PER_SEC);
  }
  const double s = median(times), cpuS = median(cpu);

  PeerRun peer;
  const std::string tckgen = findTckgen();
  const auto raw = *data / "iu_prisma_dwi";
  if (tckgen.empty()) {
    peer.note = "MRtrix tckgen is not on the PATH (Debian package mrtrix3); no comparison";
  } else if (!std::filesystem::exists(raw / "dwi.nii.gz")) {
    peer.note = "the raw DWI for tckgen is missing";
  } else {
    const auto out = std::filesystem::temp_directory_path() / ("dtf_bench_tckgen_" + std::to_string(::getpid()) + ".tck");
    std::ostringstream cmd;
    cmd << "'" << tckgen << "' '" << (raw / "dwi.nii.gz").string() << "' '" << out.string()
        << "' -algorithm Tensor_Det -fslgrad '" << (raw / "dwi.bvec").string() << "' '" << (raw / "dwi.bval").string()
        << "' -seed_image '" << (dir / "mask.nii.gz").string() << "' -mask '" << (dir / "mask.nii.gz").string()
        << "' -select " << count << " -step 1 -cutoff 0.15 -angle 60 -minlength 30 -maxlength 250 -nthreads "
        << r.threads << " -quiet -force >/dev/null 2>&1";
    const double c0 = childCpuSeconds();
    auto t2 = Clock::now();
    const int rc = std::system(cmd.str().c_str());
    peer.seconds = std::chrono::duration<double>(Clock::now() - t2).count();
    peer.cpuSeconds = childCpuSeconds() - c0;
    std::error_code ec;
    std::filesystem::remove(out, ec);
    peer.ran = rc == 0;
    if (!peer.ran) peer.note = "tckgen failed (exit status " + std::to_string(rc) + ")";
  }
  const double perS = static_cast<double>(r.lines.lineCount()) / s;
  if (json) {
    std::printf("{\"streamlines\": %zu, \"points\": %zu, \"seeds\": %zu, \"seconds\": %.3f, "
                "\"streamlines_per_s\": %.1f, "
                "\"points_per_s\": %.1f, \"seeds_per_s\": %.1f, \"cpu_s\": %.3f, \"threads\": %d, "
                "\"hardware_threads\": %u, "
                "\"integrator\": \"%s\", \"load_s\": %.3f, \"peer\": \"MRtrix tckgen -algorithm Tensor_Det\", "
                "\"peer_ran\": %s, \"peer_seconds\": %.3f, \"peer_cpu_s\": %.3f}\n",
                r.lines.lineCount(), r.lines.points.size(), r.seedsTried, s, perS,
                static_cast<double>(r.lines.points.size()) / s, static_cast<double>(r.seedsTried) / s, cpuS,
                r.threads, std::thread::hardware_concurrency(), o.rk4 ? "rk4" : "euler", loadS,
                peer.ran ? "true" : "false", peer.seconds, peer.cpuSeconds);
  } else {
    std::printf(
        "deterministic tensor tracking on the real brain (72x72x39, 3 mm), %s, step 1 mm, FA 0.15, 60 deg, "
        "30..250 mm\n",
        o.rk4 ? "RK4" : "Euler");
    std::printf("  loading tensor + mask: %.2f s\n", loadS);
    std::printf("  %zu streamlines (%zu points) from %zu seeds in %.2f s on %d threads%s\n",
                r.lines.lineCount(), r.lines.points.size(), r.seedsTried, s, r.threads,
                repeat > 1 ? " (median of repeats)" : "");
    std::printf("  CPU time %.2f s over all threads (%.0f%% of %d threads busy)\n", cpuS,
                100 * cpuS / (s * r.threads), r.threads);
    std::printf("  %.0f streamlines/s, %.0f seeds/s, %.2f M points/s\n", perS,
                static_cast<double>(r.seedsTried) / s, static_cast<double>(r.lines.points.size()) / s / 1e6);
    if (peer.ran)
      std::printf("  peer: MRtrix tckgen -algorithm Tensor_Det, same settings and %d threads: %.2f s wall, %.2f s CPU"
                  " -> dtfabric %.2fx faster (wall), %.2fx (CPU)\n",
                  r.threads, peer.seconds, peer.cpuSeconds, peer.seconds / s, peer.cpuSeconds / std::max(cpuS, 1e-9));
    else
      std::printf("  peer: %s\n", peer.note.c_str());
  }
  return 0;
}

} // namespace dtf::app
