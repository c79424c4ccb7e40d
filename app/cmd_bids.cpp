// `dtfabric bids`: the BIDS-App front end (participant and group levels) over io/bids.h, io/bids_report.h and
// app/bids_participant.h.
//
// Parallelism: the headless GL context is one per process (render::GlContext::headless() is a process
// singleton made current on one thread, and llvmpipe renders with its own thread pool), so runs are not
// rendered on parallel threads. With --jobs N > 1 the participant level starts up to N child processes of
// this same executable, one run each (`--only`), and gives each max(1, cores / N) threads for the fit and
// for llvmpipe (LP_NUM_THREADS), so N jobs never ask for more threads than the machine has cores. A child
// dies with its parent (PR_SET_PDEATHSIG): a killed run leaves no workers behind.
#include "app/args.h"
#include "app/bids_participant.h"
#include "app/commands.h"
#include "io/bids.h"
#include "io/bids_report.h"
#include "io/model/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#ifndef DTF_VERSION
#define DTF_VERSION "unknown"
#endif

namespace fs = std::filesystem;

namespace dtf::app {

namespace {

const char* kHelp = R"(usage: dtfabric bids BIDS_DIR OUTPUT_DIR participant|group [--participant-label L ...]
                     [--session-label S ...] [--jobs N] [--figure-size PX] [--force]

A BIDS App (bids_dir output_dir analysis_level). For every diffusion run sub-*/[ses-*/]dwi/*_dwi.nii[.gz]
with its .bval/.bvec:

participant  fits tensors (WLS), runs the orientation check (`dtfabric check`) and writes, under
             OUTPUT_DIR/sub-XX/[ses-YY/]dwi/ with the source name's entities kept:
               …_desc-fabricAxial_dwi.png      fabric on the axial slice through the corpus callosum
               …_desc-fabricCoronal_dwi.png    fabric on the coronal slice through the corticospinal tracts
               …_desc-fabricIsoLeft_dwi.png    fabric on the FA 0.4 isosurface, from the left
               …_desc-fabricIsoSuperior_dwi.png   the same from above
               …_desc-fabricCheck_dwi.png      the check's contact sheet (verdict corrected or inconclusive)
               …_desc-fabricMetrics_dwi.json   FA/MD in the white matter (FA >= 0.3), verdict and scores,
                                               timings, input hashes; written last
             and OUTPUT_DIR/dataset_description.json (DatasetType derivative). Slices are chosen from each
             run's data. A failing run (corrupt file, missing table, wrong volume count) is recorded with the
             file and the reason and the others go on. Every file is written atomically; a rerun skips runs
             that are complete and whose inputs and parameters are unchanged (unless --force).
group        OUTPUT_DIR/group.tsv (one row per run) and OUTPUT_DIR/group_report.html (one static page: a
             sortable table, a mosaic of every run's figures, flags for failed runs, corrected or
             inconclusive tables and outlying metrics, click-through to each run's figures).

  --participant-label L ...  only these participants ("01" or "sub-01"); unknown labels are an error
  --session-label S ...      only these sessions
  --jobs N                   runs in parallel (child processes; default: the number of cores). Threads per
                             job: max(1, cores / N) for the fit and the renderer
  --threads N                threads of each job for the fit and the renderer (LP_NUM_THREADS of workers)
  --figure-size PX           edge of each figure (default 512; the contact sheet's panels are half)
  --force                    recompute complete runs too

Exit codes: 0 ok, 1 usage, 2 bad input or any run failed (participant level), 3 GL failure.
)";

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string runLabel(const io::BidsRun& r) { return r.relDir + "/" + r.stem; }

std::string clock(double s) {
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
  else std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

// Splits the multi-valued label options off the argument list ("--participant-label 01 02 --force").
std::vector<std::string> takeList(std::vector<std::string>& argv, const std::string& name) {
  std::vector<std::string> values, rest;
  bool found = false;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    if (argv[i] == "--" + name) {
      found = true;
      for (; i + 1 < argv.size() && argv[i + 1].rfind("--", 0) != 0; ++i)
        values.push_back(argv[i + 1]);
      continue;
    }
    rest.push_back(argv[i]);
  }
  if (found && values.empty()) throw UsageError("--" + name + " needs at least one label");
  argv = rest;
  return values;
}

struct Progress {
  std::size_t total = 0, done = 0, failed = 0, skipped = 0;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();

  void report(const io::BidsRun& r, const RunOutcome& o) {
    ++done;
    failed += !o.ok;
    skipped += o.skipped;
    const double elapsed = secondsSince(t0);
    const std::size_t left = total - done;
    std::string status = o.ok ? (o.skipped ? "skipped (complete and unchanged)"
                                           : "ok, verdict " + o.verdict + ", " + clock(o.seconds))
                              : "FAILED: " + o.message;
    std::fprintf(stderr, "[%zu/%zu] %s: %s | %zu left, elapsed %s", done, total, runLabel(r).c_str(),
                 status.c_str(), left, clock(elapsed).c_str());
    if (left > 0) std::fprintf(stderr, ", ETA %s", clock(elapsed / static_cast<double>(done) * left).c_str());
    std::fprintf(stderr, "\n");
  }
};

RunOutcome outcomeFromDocument(const io::BidsRun& run, const std::string& out, double seconds) {
  RunOutcome o;
  o.seconds = seconds;
  try {
    const std::string path = metricsPath(run, out);
    const io::FlatJson doc = io::FlatJson::parse(io::readTextFile(path), path);
    o.ok = doc.get("status") == "ok";
    o.verdict = doc.get("check_verdict");
    o.message = doc.get("message");
  } catch (const Error& e) {
    o.message = e.what();
  }
  return o;
}

int runParticipants(const std::vector<io::BidsRun>& runs, const std::string& bids, const std::string& out,
                    const ParticipantOptions& opts, int jobs, bool quiet) {
  Progress progress;
  progress.total = runs.size();
  if (!quiet)
    std::fprintf(stderr, "dtfabric bids: %zu run%s, %d job%s, %d thread%s each\n", runs.size(),
                 runs.size() == 1 ? "" : "s", jobs, jobs == 1 ? "" : "s", std::max(1, opts.fitThreads),
                 opts.fitThreads == 1 ? "" : "s");
  if (jobs <= 1 || runs.size() <= 1) {
    for (const auto& r : runs) {
      if (!quiet) std::fprintf(stderr, "  running %s\n", runLabel(r).c_str());
      const RunOutcome o = processRun(r, out, opts);
      if (!quiet) progress.report(r, o);
      progress.failed += quiet && !o.ok;
    }
  } else {
    const std::string exe = fs::read_symlink("/proc/self/exe").string();
    struct Worker {
      std::size_t run;
      std::chrono::steady_clock::time_point start;
      fs::file_time_type docTime; // the metrics document's time before: unchanged means skipped
    };
    std::map<pid_t, Worker> running;
    std::size_t next = 0;
    while (next < runs.size() || !running.empty()) {
      while (next < runs.size() && running.size() < static_cast<std::size_t>(jobs)) {
        const io::BidsRun& r = runs[next];
        std::vector<std::string> args = {exe,      "bids",          bids,
                                         out,      "participant",   "--only",
                                         runLabel(r), "--jobs",     "1",
                                         "--threads", std::to_string(opts.fitThreads), "--figure-size",
                                         std::to_string(opts.figurePx)};
        if (opts.force) args.push_back("--force");
        const std::string lp = std::to_string(opts.fitThreads);
        const pid_t parent = ::getpid();
        const pid_t pid = ::fork();
        if (pid < 0) throw InputError("cannot start a worker process (fork failed)");
        if (pid == 0) {
          ::prctl(PR_SET_PDEATHSIG, SIGKILL);
          if (::getppid() != parent) ::_exit(2);
          if (!std::getenv("LP_NUM_THREADS")) ::setenv("LP_NUM_THREADS", lp.c_str(), 1);
          std::vector<char*> cargs;
          for (auto& a : args)
            cargs.push_back(a.data());
          cargs.push_back(nullptr);
          ::execv(exe.c_str(), cargs.data());
          ::_exit(127);
        }
        std::fprintf(stderr, "  running %s (worker %d)\n", runLabel(r).c_str(), static_cast<int>(pid));
        std::error_code ec;
        const fs::file_time_type docTime = fs::last_write_time(metricsPath(r, out), ec);
        running[pid] = {next++, std::chrono::steady_clock::now(), ec ? fs::file_time_type::min() : docTime};
      }
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (pid < 0) break;
      auto it = running.find(pid);
      if (it == running.end()) continue;
      const io::BidsRun& r = runs[it->second.run];
      RunOutcome o = outcomeFromDocument(r, out, secondsSince(it->second.start));
      std::error_code ec;
      o.skipped = o.ok && it->second.docTime != fs::file_time_type::min() &&
                  fs::last_write_time(metricsPath(r, out), ec) == it->second.docTime;
      if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 2)) {
        o.ok = false;
        o.message = "worker for " + r.dwi + " ended " +
                    (WIFSIGNALED(status) ? "by signal " + std::to_string(WTERMSIG(status))
                                         : "with exit code " + std::to_string(WEXITSTATUS(status)));
      }
      running.erase(it);
      progress.report(r, o);
    }
  }
  if (!quiet)
    std::fprintf(stderr, "dtfabric bids: %zu run%s in %s: %zu ok (%zu unchanged), %zu failed\n", progress.total,
                 progress.total == 1 ? "" : "s", clock(secondsSince(progress.t0)).c_str(),
                 progress.total - progress.failed, progress.skipped, progress.failed);
  return progress.failed ? 2 : 0;
}

int runGroup(const io::BidsDataset& ds, const std::vector<io::BidsRun>& runs, const std::string& out) {
  std::vector<io::GroupRow> rows;
  for (const auto& r : runs)
    rows.push_back(readGroupRow(r, out));
  io::flagOutliers(rows);
  std::error_code ec;
  fs::create_directories(out, ec);
  const std::string tsv = (fs::path(out) / "group.tsv").string();
  const std::string html = (fs::path(out) / "group_report.html").string();
  io::writeTextIfChanged(tsv, io::groupTsv(rows));
  const std::string title = "dtfabric quality report" + (ds.name.empty() ? "" : ": " + ds.name);
  io::writeTextIfChanged(html, io::groupReportHtml(rows, title,
                                                   "dtfabric " + std::string(DTF_VERSION) + " over " + ds.root));
  std::size_t failed = 0, flagged = 0;
  for (const auto& r : rows) {
    failed += !r.ok;
    flagged += r.ok && (r.verdict != "ok" || !r.outliers.empty());
  }
  std::printf("wrote %s and %s: %zu runs, %zu failed, %zu flagged\n", tsv.c_str(), html.c_str(), rows.size(),
              failed, flagged);
  return 0;
}

} // namespace

int cmdBids(const CommandArgs& argvIn) {
  CommandArgs argv = argvIn;
  const auto participants = takeList(argv, "participant-label");
  const auto sessions = takeList(argv, "session-label");
  Args args(argv, {"help", "force"});
  if (args.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::string bids = args.positional(0, "BIDS_DIR (see --help)");
  const std::string out = args.positional(1, "OUTPUT_DIR");
  const std::string level = args.positional(2, "the analysis level, participant or group");
  if (args.positionals().size() > 3) throw UsageError("unexpected argument '" + args.positionals()[3] + "'");
  if (level != "participant" && level != "group")
    throw UsageError("the analysis level must be participant or group, got '" + level + "'");
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int jobs = args.getInt("jobs", cores);
  if (jobs < 1 || jobs > 256) throw UsageError("--jobs must be in [1, 256]");
  ParticipantOptions opts;
  opts.figurePx = args.getInt("figure-size", 512);
  if (opts.figurePx < 64 || opts.figurePx > 2048) throw UsageError("--figure-size must be in [64, 2048] pixels");
  opts.force = args.flag("force");
  opts.version = DTF_VERSION;
  const std::string only = args.getOr("only", ""); // internal: one run (RELDIR/STEM), for the workers
  opts.fitThreads = args.getInt("threads", std::max(1, cores / jobs));
  if (opts.fitThreads < 1 || opts.fitThreads > 1024) throw UsageError("--threads must be in [1, 1024]");
  args.finish();

  const io::BidsDataset ds = io::scanBidsDataset(bids);
  io::refuseOutputInsideInput(bids, out);
  std::vector<io::BidsRun> runs = io::selectRuns(ds, participants, sessions);
  if (!only.empty()) {
    std::erase_if(runs, [&](const io::BidsRun& r) { return runLabel(r) != only; });
    if (runs.empty()) throw InputError(bids + ": no diffusion run " + only);
  }
  if (runs.empty())
    throw InputError(bids + ": no diffusion run (sub-*/[ses-*/]dwi/*_dwi.nii[.gz]) among the selected participants");
  if (level == "group") return runGroup(ds, runs, out);

  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError("cannot create " + out + ": " + ec.message());
  io::writeDerivativeDescription(out, ds, DTF_VERSION);
  return runParticipants(runs, bids, out, opts, jobs, !only.empty());
}

} // namespace dtf::app
