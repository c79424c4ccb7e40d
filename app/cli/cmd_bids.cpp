// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bids`: the BIDS-App front end (participant and group levels) over io/bids/bids.h, io/bids/bids_report.h and
// app/bids_participant.h.
//
// Parallelism: the headless GL context is one per process (render::GlContext::headless() is a process
// singleton made current on one thread, and llvmpipe renders with its own thread pool), so runs are not
// rendered on parallel threads. With --jobs N > 1 the participant level starts a pool of up to N worker
// processes of this same executable (`--worker`: run labels on stdin, one "done" line per run on stdout),
// each processing runs one after the other in its own GL context, with max(1, cores / N) threads for the fit
// and for llvmpipe (LP_NUM_THREADS), so N jobs never ask for more threads than the machine has cores. A
// worker dies with its parent (PR_SET_PDEATHSIG): a killed run leaves no workers behind.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "ui/session/bids_participant.h"
#include "io/bids/bids.h"
#include "io/bids/bids_report.h"
#include "io/model/error.h"
#include "io/formats/json.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <poll.h>
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

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string runLabel(const io::BidsRun& r) {
  return r.relDir + "/" + r.stem;
}

std::string clock(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.1f s", s);
  else
    std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

struct Progress {
  std::size_t total = 0, done = 0, failed = 0, skipped = 0;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();

  void report(const io::BidsRun& r, const session::RunOutcome& o) {
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

session::RunOutcome outcomeFromDocument(const io::BidsRun& run, const std::string& out, double seconds) {
  session::RunOutcome o;
  o.seconds = seconds;
  try {
    const std::string path = session::metricsPath(run, out);
    const nlohmann::ordered_json doc = io::readJsonFile(path);
    o.ok = io::jsonString(doc, "status") == "ok";
    o.verdict = io::jsonString(doc, "check_verdict");
    o.message = io::jsonString(doc, "message");
  } catch (const Error& e) {
    o.message = e.what();
  }
  return o;
}

// A pool of worker processes (this executable with --worker): each reads run labels on its stdin, processes
// them one after the other in one GL context, and answers "done" on its stdout. A worker that dies fails
// only the run it was processing; a new worker takes the rest.
class WorkerPool {
public:
  WorkerPool(const std::vector<io::BidsRun>& runs, const std::string& bids, const std::string& out,
             const session::ParticipantOptions& opts, Progress& progress)
      : runs_(runs), bids_(bids), out_(out), opts_(opts), progress_(progress),
        exe_(fs::read_symlink("/proc/self/exe").string()) {}
  ~WorkerPool() {
    for (auto& w : workers_) {
      if (w.in >= 0) ::close(w.in);
      if (w.out >= 0) ::close(w.out);
      if (w.pid > 0) ::waitpid(w.pid, nullptr, 0);
    }
  }

  void run(std::size_t poolSize) {
    std::signal(SIGPIPE, SIG_IGN); // a worker that died is noticed on its stdout, not by a signal here
    for (std::size_t i = 0; i < poolSize; ++i)
      spawn();
    for (auto& w : workers_)
      assign(w);
    while (true) {
      std::vector<pollfd> fds;
      std::vector<std::size_t> which;
      for (std::size_t i = 0; i < workers_.size(); ++i)
        if (workers_[i].run >= 0) {
          fds.push_back({workers_[i].out, POLLIN, 0});
          which.push_back(i);
        }
      if (fds.empty()) break;
      if (::poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        throw InputError("waiting for the workers failed");
      }
      for (std::size_t f = 0; f < fds.size(); ++f)
        if (fds[f].revents) readFrom(which[f]);
    }
  }

private:
  struct Worker {
    pid_t pid = -1;
    int in = -1, out = -1;
    long run = -1; // index of the run it is processing, -1 when idle
    std::chrono::steady_clock::time_point start;
    fs::file_time_type docTime; // the metrics document's time before: unchanged means skipped
    std::string buffer;
  };

  void spawn() {
    int toChild[2], fromChild[2];
    if (::pipe2(toChild, O_CLOEXEC) != 0 || ::pipe2(fromChild, O_CLOEXEC) != 0)
      throw InputError("cannot start a worker process (pipe failed)");
    std::vector<std::string> args = {exe_,          "bids",     bids_, out_, "participant", "--worker", "--jobs", "1",
                                     "--threads",   std::to_string(opts_.fitThreads),
                                     "--figure-size", std::to_string(opts_.figurePx)};
    if (opts_.force) args.push_back("--force");
    if (opts_.webPx > 0) {
      args.push_back("--web");
      args.push_back("--web-size");
      args.push_back(std::to_string(opts_.webPx));
    }
    const std::string lp = std::to_string(opts_.fitThreads);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) throw InputError("cannot start a worker process (fork failed)");
    if (pid == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(2);
      ::dup2(toChild[0], 0);
      ::dup2(fromChild[1], 1);
      if (!std::getenv("LP_NUM_THREADS")) ::setenv("LP_NUM_THREADS", lp.c_str(), 1);
      std::vector<char*> cargs;
      for (auto& a : args)
        cargs.push_back(a.data());
      cargs.push_back(nullptr);
      ::execv(exe_.c_str(), cargs.data());
      ::_exit(127);
    }
    ::close(toChild[0]);
    ::close(fromChild[1]);
    Worker w;
    w.pid = pid;
    w.in = toChild[1];
    w.out = fromChild[0];
    workers_.push_back(w);
  }

  // The next run to `w`, or its stdin closed when none is left.
  void assign(Worker& w) {
    w.run = -1;
    if (next_ >= runs_.size()) {
      if (w.in >= 0) ::close(w.in);
      w.in = -1;
      return;
    }
    const io::BidsRun& r = runs_[next_];
    const std::string line = runLabel(r) + "\n";
    if (::write(w.in, line.data(), line.size()) != static_cast<ssize_t>(line.size()))
      return; // died: seen when its stdout ends
    w.run = static_cast<long>(next_++);
    w.start = std::chrono::steady_clock::now();
    std::error_code ec;
    w.docTime = fs::last_write_time(session::metricsPath(r, out_), ec);
    if (ec) w.docTime = fs::file_time_type::min();
    std::fprintf(stderr, "  running %s (worker %d)\n", runLabel(r).c_str(), static_cast<int>(w.pid));
  }

  void readFrom(std::size_t wi) {
    char buf[256];
    const ssize_t n = ::read(workers_[wi].out, buf, sizeof buf);
    if (n > 0) {
      workers_[wi].buffer.append(buf, static_cast<std::size_t>(n));
      std::size_t eol;
      while (workers_[wi].run >= 0 && (eol = workers_[wi].buffer.find('\n')) != std::string::npos) {
        workers_[wi].buffer.erase(0, eol + 1);
        runDone(workers_[wi]);
        assign(workers_[wi]);
      }
      return;
    }
    if (n < 0 && errno == EINTR) return;
    workerEnded(wi);
  }

  void runDone(const Worker& w) {
    const io::BidsRun& r = runs_[static_cast<std::size_t>(w.run)];
    session::RunOutcome o = outcomeFromDocument(r, out_, secondsSince(w.start));
    std::error_code ec;
    o.skipped = o.ok && w.docTime != fs::file_time_type::min() &&
                fs::last_write_time(session::metricsPath(r, out_), ec) == w.docTime;
    progress_.report(r, o);
  }

  // The worker ended while processing a run: that run failed; a new worker takes the rest.
  void workerEnded(std::size_t wi) {
    Worker& w = workers_[wi];
    int status = 0;
    ::waitpid(w.pid, &status, 0);
    const io::BidsRun& r = runs_[static_cast<std::size_t>(w.run)];
    session::RunOutcome o;
    o.seconds = secondsSince(w.start);
    o.message = "the worker processing " + r.dwi + " ended " +
                (WIFSIGNALED(status) ? "by signal " + std::to_string(WTERMSIG(status))
                                     : "with exit code " + std::to_string(WEXITSTATUS(status)));
    progress_.report(r, o);
    ::close(w.out);
    if (w.in >= 0) ::close(w.in);
    w.run = -1;
    w.in = w.out = -1;
    w.pid = -1;
    if (next_ < runs_.size()) {
      spawn(); // invalidates `w`
      assign(workers_.back());
    }
  }

  const std::vector<io::BidsRun>& runs_;
  const std::string& bids_;
  const std::string& out_;
  const session::ParticipantOptions& opts_;
  Progress& progress_;
  const std::string exe_;
  std::vector<Worker> workers_;
  std::size_t next_ = 0;
};

int runParticipants(const std::vector<io::BidsRun>& runs, const std::string& bids, const std::string& out,
                    const session::ParticipantOptions& opts, int jobs) {
  Progress progress;
  progress.total = runs.size();
  std::fprintf(stderr, "dtfabric bids: %zu run%s, %d job%s, %d thread%s each\n", runs.size(),
               runs.size() == 1 ? "" : "s", jobs, jobs == 1 ? "" : "s", std::max(1, opts.fitThreads),
               opts.fitThreads == 1 ? "" : "s");
  if (jobs <= 1 || runs.size() <= 1) {
    for (const auto& r : runs) {
      std::fprintf(stderr, "  running %s\n", runLabel(r).c_str());
      progress.report(r, session::processRun(r, out, opts));
    }
  } else {
    WorkerPool(runs, bids, out, opts, progress).run(std::min(runs.size(), static_cast<std::size_t>(jobs)));
  }
  std::fprintf(stderr, "dtfabric bids: %zu run%s in %s: %zu ok (%zu unchanged), %zu failed\n", progress.total,
               progress.total == 1 ? "" : "s", clock(secondsSince(progress.t0)).c_str(),
               progress.total - progress.failed, progress.skipped, progress.failed);
  return progress.failed ? 2 : 0;
}

int runGroup(const io::BidsDataset& ds, const std::vector<io::BidsRun>& runs, const std::string& out) {
  std::vector<io::GroupRow> rows;
  for (const auto& r : runs)
    rows.push_back(session::readGroupRow(r, out));
  io::flagOutliers(rows);
  std::error_code ec;
  fs::create_directories(out, ec);
  const std::string tsv = (fs::path(out) / "group.tsv").string();
  const std::string html = (fs::path(out) / "group_report.html").string();
  io::writeTextIfChanged(tsv, io::groupTsv(rows));
  const std::string title = "dtfabric quality report" + (ds.name.empty() ? "" : ": " + ds.name);
  io::writeTextIfChanged(
      html, io::groupReportHtml(rows, title, "dtfabric " + std::string(DTF_VERSION) + " over " + ds.root));
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

const OptionTable& bidsOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bids";
    t.positionals = "BIDS_DIR OUTPUT_DIR participant|group";
    t.maxPositionals = 3;
    t.intro =
        "A BIDS App (bids_dir output_dir analysis_level). For every diffusion run sub-*/[ses-*/]dwi/*_dwi.nii[.gz]\n"
        "with its .bval/.bvec:\n"
        "\n"
        "participant  fits tensors (WLS), runs the orientation check (`dtfabric check`) and writes, under\n"
        "             OUTPUT_DIR/sub-XX/[ses-YY/]dwi/ with the source name's entities kept:\n"
        "               …_desc-fabricAxial_dwi.png      fabric on the axial slice through the corpus callosum\n"
        "               …_desc-fabricCoronal_dwi.png    fabric on the coronal slice through the corticospinal tracts\n"
        "               …_desc-fabricIsoLeft_dwi.png    fabric on the FA 0.4 isosurface, from the left\n"
        "               …_desc-fabricIsoSuperior_dwi.png   the same from above\n"
        "               …_desc-fabricCheck_dwi.png      the check's contact sheet (verdict corrected or inconclusive)\n"
        "               …_desc-fabricWeb_dwi/index.html with --web: the web page of every slice (`dtfabric web`)\n"
        "               …_desc-fabricMetrics_dwi.json   FA/MD in the white matter (FA >= 0.3), verdict and scores,\n"
        "                                               timings, input hashes; written last\n"
        "             and OUTPUT_DIR/dataset_description.json (DatasetType derivative). Slices are chosen from each\n"
        "             run's data. A failing run (corrupt file, missing table, wrong volume count) is recorded with the\n"
        "             file and the reason and the others go on. Every file is written atomically; a rerun skips runs\n"
        "             that are complete and whose inputs and parameters are unchanged (unless --force).\n"
        "group        OUTPUT_DIR/group.tsv (one row per run) and OUTPUT_DIR/group_report.html (one static page: a\n"
        "             sortable table, a mosaic of every run's figures, flags for failed runs, corrected or\n"
        "             inconclusive tables and outlying metrics, click-through to each run's figures).";
    t.options = {
        O::list("participant-label", "L",
                "only these participants (\"01\" or \"sub-01\"); unknown labels are an error"),
        O::list("session-label", "S", "only these sessions"),
        O::integer(
            "jobs", "N", 1, closedRange(1, 256),
            "runs in parallel (child processes). Threads per job: max(1, cores / N) for the fit and the "
            "renderer")
            .defaultSays("the number of cores"),
        O::integer("threads", "N", 1, closedRange(1, 1024),
                   "threads of each job for the fit and the renderer (LP_NUM_THREADS of workers)")
            .defaultSays("max(1, cores / N of --jobs)"),
        O::integer("figure-size", "PX", session::ParticipantOptions{}.figurePx, closedRange(64, 2048),
                   "edge of each figure (the contact sheet's panels are half)"),
        O::flag("web", "participant level: also each run's web page (`dtfabric web`: every slice, in any "
                       "browser), …_desc-fabricWeb_dwi/index.html; the group report links it"),
        O::integer("web-size", "PX", 256, closedRange(16, 2048), "the web page's slice images (longer side)")
            .measuredIn("pixels"),
        O::flag("force", "recompute complete runs too"),
        O::flag("worker", "a pool worker of --jobs (run labels on stdin, \"done\" on stdout)").internalOnly(),
    };
    t.epilogue =
        "Exit codes: 0 ok, 1 usage, 2 bad input or any run failed (participant level; a GL failure while\n"
        "rendering a run is recorded as that run's failure).";
    return t;
  }();
  return table;
}

int cmdBids(const CommandArgs& argv) {
  ParsedOptions args(bidsOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const auto participants = args.list("participant-label");
  const auto sessions = args.list("session-label");
  const std::string bids = args.positional(0, "BIDS_DIR (see --help)");
  const std::string out = args.positional(1, "OUTPUT_DIR");
  const std::string level = args.positional(2, "the analysis level, participant or group");
  if (level != "participant" && level != "group")
    throw UsageError("the analysis level must be participant or group, got '" + level + "'");
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int jobs = args.given("jobs") ? args.integer("jobs") : cores;
  session::ParticipantOptions opts;
  opts.figurePx = args.integer("figure-size");
  opts.force = args.flag("force");
  const bool web = args.flag("web");
  const int webSize = args.integer("web-size");
  if (!web && args.given("web-size")) throw UsageError("--web-size needs --web");
  opts.webPx = web ? webSize : 0;
  opts.version = DTF_VERSION;
  const bool worker = args.flag("worker"); // a pool worker (run labels on stdin, "done" on stdout)
  opts.fitThreads = args.given("threads") ? args.integer("threads") : std::max(1, cores / jobs);
  args.finish();

  const io::BidsDataset ds = io::scanBidsDataset(bids);
  io::refuseOutputInsideInput(bids, out);
  std::vector<io::BidsRun> runs = io::selectRuns(ds, participants, sessions);
  if (runs.empty())
    throw InputError(bids +
                     ": no diffusion run (sub-*/[ses-*/]dwi/*_dwi.nii[.gz]) among the selected participants");
  if (level == "group") return runGroup(ds, runs, out);

  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError("cannot create " + out + ": " + ec.message());
  io::writeDerivativeDescription(out, ds, DTF_VERSION);
  if (worker) {
    for (std::string label; std::getline(std::cin, label);) {
      for (const auto& r : runs)
        if (runLabel(r) == label) session::processRun(r, out, opts);
      std::cout << "done" << std::endl;
    }
    return 0;
  }
  return runParticipants(runs, bids, out, opts, jobs);
}

} // namespace dtf::app
