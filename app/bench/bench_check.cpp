// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench check`: the orientation check on the real DWI (load, WLS fit, 24 candidate scores) against
// MRtrix's dwigradcheck (Debian mrtrix3; a peer run in the same invocation when on the PATH, never a
// dependency) on the same DWI, table and mask. dwigradcheck tracks streamlines for every candidate table;
// we fit once and turn the tensors. Reports both times, the speed-up and whether both chose the same table.
#include "app/bench/bench.h"
#include "io/formats/process.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "ui/session/check_run.h"
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/formats/json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace dtf::app {

namespace {

struct Peer {
  bool ran = false;
  double seconds = 0;
  std::string note;
  std::string choice; // the table it chose, as a transform of the given one ("x y z" = unchanged)
};

// The candidate M with exported = +-M * given for every diffusion-weighted direction, or "" when none fits.
std::string identifyTable(const std::vector<glm::dvec3>& given, const std::vector<glm::dvec3>& exported,
                          const std::vector<double>& bvals) {
  if (given.size() != exported.size()) return {};
  for (const auto& m : surfaces::orientationCandidates()) {
    bool all = true;
    for (std::size_t n = 0; n < given.size() && all; ++n) {
      if (!(bvals[n] > 50)) continue;
      const glm::dvec3 g = m.apply(glm::normalize(given[n])), e = glm::normalize(exported[n]);
      all = std::abs(std::abs(glm::dot(g, e)) - 1.0) < 1e-3;
    }
    if (all) return m.name();
  }
  return {};
}

} // namespace

const OptionTable& benchCheckOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench check";
    t.intro =
        "Times `dtfabric check` on the real DWI (iu_prisma_dwi: load, WLS fit in mask.nii.gz, 24 candidate\n"
        "scores; median of R runs) and, when MRtrix's dwigradcheck is on the PATH (Debian mrtrix3),\n"
        "dwigradcheck on the same DWI, table and mask with T threads; prints both times, the speed-up and\n"
        "whether both chose the same table.";
    t.options = {
        O::integer("repeat", "R", 5, closedRange(1, 100), "runs of our check"),
        O::integer("threads", "T", 1, atLeast(1), "dwigradcheck's threads").defaultSays("all cores"),
        O::flag("no-peer", "skip dwigradcheck"),
        O::flag("json", "one JSON object"),
        sharedDataOption(),
    };
    return t;
  }();
  return table;
}

int benchCheck(const CommandArgs& argv) {
  ParsedOptions args(benchCheckOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const bool json = args.flag("json");
  const bool noPeer = args.flag("no-peer");
  const int repeat = args.integer("repeat");
  const int threads = args.given("threads") ? args.integer("threads")
                                            : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const auto data = findSharedDataDir(args.get("data"));
  args.finish();
  if (!data || !std::filesystem::exists(*data / "iu_prisma_dwi/dwi.nii.gz"))
    throw InputError(
        "the real data (iu_prisma_dwi/dwi.nii.gz) was not found; give --data DIR or set DTF_SHARED_DATA");
  const auto dir = *data / "iu_prisma_dwi";

  session::CheckRequest req;
  req.input = (dir / "dwi.nii.gz").string();
  req.bval = (dir / "dwi.bval").string();
  req.bvec = (dir / "dwi.bvec").string();
  req.mask = (dir / "derived" / "mask.nii.gz").string();
  using Clock = std::chrono::steady_clock;
  std::vector<double> total, load, fit, score;
  session::CheckRun run;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = Clock::now();
    run = session::runCheck(req);
    total.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    load.push_back(run.loadSeconds);
    fit.push_back(run.fitSeconds);
    score.push_back(run.checkSeconds);
  }
  const double ours = median(total);
  const std::string ourChoice = run.report.candidates[run.report.best].transform.name();

  Peer peer;
  const std::string exe = noPeer ? std::string() : io::findOnPath("dwigradcheck");
  if (noPeer) {
    peer.note = "skipped (--no-peer)";
  } else if (exe.empty()) {
    peer.note = "MRtrix dwigradcheck is not on the PATH (Debian package mrtrix3); no comparison";
  } else {
    const auto tmp =
        std::filesystem::temp_directory_path() / ("dtf_bench_gradcheck_" + std::to_string(::getpid()));
    std::filesystem::create_directories(tmp);
    const std::string log = (tmp / "log.txt").string();
    const auto t1 = Clock::now();
    const int rc = io::runProgram({exe, req.input, "-fslgrad", req.bvec, req.bval, "-mask", req.mask,
                                   "-export_grad_fsl", (tmp / "out.bvec").string(), (tmp / "out.bval").string(),
                                   "-scratch", tmp.string(), "-nthreads", std::to_string(threads), "-force",
                                   "-quiet"},
                                  {log, log, {}});
    peer.seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    peer.ran = rc == 0 && std::filesystem::exists(tmp / "out.bvec");
    if (!peer.ran) {
      peer.note = "dwigradcheck failed (exit status " + std::to_string(rc) + ")";
    } else {
      try {
        peer.choice = identifyTable(run.bvecs, io::readBvecs((tmp / "out.bvec").string()), run.bvals);
        if (peer.choice.empty()) peer.note = "its exported table is no signed permutation of the given one";
      } catch (const Error& e) {
        peer.note = std::string("its exported table could not be read: ") + e.what();
      }
    }
    std::error_code ec;
    std::filesystem::remove_all(tmp, ec);
  }
  const bool same = peer.ran && peer.choice == ourChoice;
  if (json) {
    const nlohmann::ordered_json j = {{"bench", "check"},
                                      {"data", req.input},
                                      {"repeat", repeat},
                                      {"seconds", ours},
                                      {"load_s", median(load)},
                                      {"fit_s", median(fit)},
                                      {"score_s", median(score)},
                                      {"verdict", surfaces::verdictName(run.report.verdict)},
                                      {"choice", ourChoice},
                                      {"margin", run.report.margin},
                                      {"white_matter_voxels", run.report.whiteMatterVoxels},
                                      {"peer", "MRtrix dwigradcheck"},
                                      {"peer_ran", peer.ran},
                                      {"peer_seconds", peer.seconds},
                                      {"peer_threads", threads},
                                      {"peer_choice", peer.choice},
                                      {"speedup", peer.ran ? peer.seconds / ours : 0.0},
                                      {"same_table", same},
                                      {"peer_note", peer.note}};
    std::printf("%s\n", io::jsonText(j).c_str());
    return 0;
  }
  std::printf("bench check: %s, mask %s\n", req.input.c_str(), req.mask.c_str());
  std::printf("  dtfabric check: %.3f s (median of %d: load %.3f s, WLS fit %.3f s, 24 scores %.2f ms)\n",
              ours, repeat, median(load), median(fit), 1e3 * median(score));
  std::printf("    verdict %s, chose [%s], margin %.1f%%, %zu white-matter voxels\n",
              surfaces::verdictName(run.report.verdict), ourChoice.c_str(), 100 * run.report.margin,
              run.report.whiteMatterVoxels);
  if (peer.ran)
    std::printf(
        "  peer: MRtrix dwigradcheck, %d threads: %.2f s, chose [%s]%s\n  speed-up %.0fx; same table: %s\n",
        threads, peer.seconds, peer.choice.c_str(), peer.note.empty() ? "" : (" (" + peer.note + ")").c_str(),
        peer.seconds / ours, same ? "yes" : "no");
  else
    std::printf("  peer: %s\n", peer.note.c_str());
  return 0;
}

} // namespace dtf::app
