// SPDX-License-Identifier: GPL-3.0-or-later
// Tractogram load figures of `bench io`: the 36,763-streamline stroke.trk.gz (gzip TrackVis, LAS) against
// nibabel's load of the same file in the same run, and a TRX zip of 1 M streamlines (12 points each,
// float32 positions stored uncompressed, one per-streamline and one per-point array) written here.
#include "app/bench/bench.h"
#include "io/formats/process.h"
#include "io/model/error.h"
#include "io/formats/trx.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <unistd.h>

namespace dtf::app {

namespace {
namespace fs = std::filesystem;

// Median wall and process-CPU seconds of `runs` calls.
std::pair<double, double> timeRuns(int runs, const std::function<void()>& f) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    f();
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return {median(wall), median(cpu)};
}

// nibabel's median load wall and process-CPU seconds of `file` over `runs` loads (the whole tractogram,
// not lazily), or -1.
std::pair<double, double> nibabelLoadSeconds(const fs::path& file, int runs) {
  const std::string script = "import sys, time, statistics, nibabel\n"
                             "t, c = [], []\n"
                             "for _ in range(" +
                             std::to_string(runs) +
                             "):\n"
                             "    t0, c0 = time.perf_counter(), time.process_time()\n"
                             "    s = nibabel.streamlines.load(sys.argv[1]).streamlines\n"
                             "    t.append(time.perf_counter() - t0)\n"
                             "    c.append(time.process_time() - c0)\n"
                             "print('DTF_NIBABEL', statistics.median(t), statistics.median(c), len(s))\n";
  const fs::path out = fs::temp_directory_path() / ("dtf_bench_nibabel_" + std::to_string(::getpid()) + ".txt");
  for (const char* py : {"/usr/bin/python3", "python3"}) {
    if (io::runProgram({py, "-c", script, file.string()}, {out.string(), "/dev/null", {}}) != 0) continue;
    double seconds = -1, cpu = -1;
    long count = 0;
    std::ifstream lines(out);
    for (std::string line; std::getline(lines, line);)
      if (std::sscanf(line.c_str(), "DTF_NIBABEL %lf %lf %ld", &seconds, &cpu, &count) == 3) break;
    std::error_code ec;
    fs::remove(out, ec);
    if (seconds > 0) return {seconds, cpu};
  }
  return {-1, -1};
}
} // namespace

std::vector<TractLoadFigure> benchTractLoads(const std::optional<fs::path>& dataDir,
                                             std::vector<std::string>& notes) {
  std::vector<TractLoadFigure> out;
  const fs::path stroke = dataDir ? *dataDir / "niivue_tracts" / "stroke.trk.gz" : fs::path();
  TractLoadFigure trk{
      "trk_gz_load_s", "load stroke.trk.gz (36,763 lines)", "faster than nibabel", -1, -1, -1};
  TractLoadFigure nib{"trk_gz_load_nibabel_s", "  nibabel 5 load, same file", "(reference)", -1, -1, -1};
  if (dataDir && fs::exists(stroke)) {
    std::size_t lines = 0;
    session::readTracts(stroke.string()); // warm the page cache
    std::tie(trk.wall, trk.cpu) =
        timeRuns(5, [&] { lines = session::readTracts(stroke.string()).lineCount(); });
    if (lines != 36763)
      notes.push_back("stroke.trk.gz held " + std::to_string(lines) + " streamlines, not 36763");
    std::tie(nib.wall, nib.cpu) = nibabelLoadSeconds(stroke, 5);
    nib.goal = nib.wall; // a reference row, not a goal of its own
    if (nib.wall > 0) {
      trk.goal = nib.wall;
      char ratio[96];
      std::snprintf(ratio, sizeof ratio, "stroke.trk.gz: dtfabric %.1fx faster than nibabel",
                    nib.wall / trk.wall);
      notes.push_back(ratio);
    } else {
      notes.push_back("nibabel comparison skipped: no python3 with nibabel");
    }
  } else {
    notes.push_back("stroke.trk.gz load skipped: no niivue_tracts data found (use --data DIR)");
  }
  out.push_back(trk);
  if (nib.wall > 0) out.push_back(nib);

  TractLoadFigure trx{"trx_1m_load_s", "load TRX 1M lines, 12M points", "< 1 s", -1, -1, 1.0};
  const fs::path dir = fs::temp_directory_path() / ("dtfabric-bench-trx-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::create_directories(dir, ec);
  try {
    Polylines big;
    const std::size_t n = 1000000, per = 12;
    big.points.reserve(n * per);
    big.offsets.reserve(n + 1);
    big.offsets.push_back(0);
    TractValues len{"length", 1, std::vector<float>(n)}, t{"t", 1, std::vector<float>(n * per)};
    for (std::size_t l = 0; l < n; ++l) {
      const float a = static_cast<float>(l) * 0.001f;
      for (std::size_t i = 0; i < per; ++i) {
        big.points.emplace_back(60.0f * std::cos(a) + static_cast<float>(i), 60.0f * std::sin(a),
                                0.5f * static_cast<float>(i));
        t.values[l * per + i] = static_cast<float>(i) / per;
      }
      big.offsets.push_back(static_cast<std::uint32_t>(big.points.size()));
      len.values[l] = static_cast<float>(per - 1);
    }
    big.perLine = {std::move(len)};
    big.perPoint = {std::move(t)};
    const std::string file = (dir / "bench_1m.trx").string();
    io::writeTrx(file, big, Grid::fromAffine({181, 217, 181}, glm::dmat4(1.0)));
    big = Polylines{};
    std::size_t lines = 0;
    io::readTrx(file); // warm the page cache
    std::tie(trx.wall, trx.cpu) = timeRuns(3, [&] { lines = io::readTrx(file).lineCount(); });
    if (lines != 1000000) notes.push_back("the 1M TRX read back " + std::to_string(lines) + " streamlines");
  } catch (const Error& e) {
    notes.push_back(std::string("TRX load skipped: ") + e.what());
  }
  fs::remove_all(dir, ec);
  out.push_back(trx);
  return out;
}

} // namespace dtf::app
