// `dtfabric bench tracts`: throughput of deterministic tensor tracking on the real brain with the settings
// of the reference tracks (MRtrix tckgen -algorithm Tensor_Det: seeds and mask from mask.nii.gz, step 1 mm,
// FA cutoff 0.15, 60 deg, min length 30 mm). The peer, tckgen, is not installed here, so only our figures
// are reported.
#include "app/args.h"
#include "app/bench.h"
#include "io/model/error.h"
#include "io/tensor_io.h"
#include "surfaces/tracking.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <thread>

namespace dtf::app {

int benchTracts(const CommandArgs& argv) {
  Args args(argv, {"json", "help", "euler"});
  if (args.flag("help")) {
    std::printf(
        "usage: dtfabric bench tracts [--count N] [--threads T] [--euler] [--repeat R] [--json] [--data "
        "DIR]\n"
        "Times selecting N (default 100000) deterministic tensor streamlines on the real brain\n"
        "(iu_prisma_dwi/derived/dti_tensor.nii.gz, seeds and stop mask from mask.nii.gz, step 1 mm, FA "
        "0.15,\n"
        "60 deg, length 30..250 mm, RK4 unless --euler) on all cores. Peer: MRtrix tckgen -algorithm\n"
        "Tensor_Det (not installed here).\n");
    return 0;
  }
  const int count = args.getInt("count", 100000);
  const int threads = args.getInt("threads", 0);
  const int repeat = std::max(1, args.getInt("repeat", 1));
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
  const double perS = static_cast<double>(r.lines.lineCount()) / s;
  if (json) {
    std::printf("{\"streamlines\": %zu, \"points\": %zu, \"seeds\": %zu, \"seconds\": %.3f, "
                "\"streamlines_per_s\": %.1f, "
                "\"points_per_s\": %.1f, \"seeds_per_s\": %.1f, \"cpu_s\": %.3f, \"threads\": %d, "
                "\"hardware_threads\": %u, "
                "\"integrator\": \"%s\", \"load_s\": %.3f, \"peer\": \"MRtrix tckgen -algorithm Tensor_Det "
                "(not installed)\"}\n",
                r.lines.lineCount(), r.lines.points.size(), r.seedsTried, s, perS,
                static_cast<double>(r.lines.points.size()) / s, static_cast<double>(r.seedsTried) / s, cpuS,
                r.threads, std::thread::hardware_concurrency(), o.rk4 ? "rk4" : "euler", loadS);
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
    std::printf("  peer: MRtrix tckgen -algorithm Tensor_Det is not installed here; no comparison figures\n");
  }
  return 0;
}

} // namespace dtf::app
