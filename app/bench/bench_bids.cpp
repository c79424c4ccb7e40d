// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench bids`: seconds per run of the participant level on the real DWI (fit, orientation check and
// the four figures, in this process with every core), and the group level's time for a cohort of a few
// hundred runs (the measured rows replicated), with the report's load time in headless Chromium when it is
// on the PATH (a peer measurement, never a dependency).
#include "app/bench/bench.h"
#include "io/formats/process.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "ui/session/bids_participant.h"
#include "io/bids/bids.h"
#include "io/bids/bids_report.h"
#include "io/model/error.h"
#include "io/formats/json.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
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

// Wall seconds of `chromium --headless --dump-dom URL`, -1 when it fails; the dumped page in `dom`.
double chromiumSeconds(const std::string& chromium, const std::string& url, const fs::path& scratch,
                       std::string* dom = nullptr) {
  const fs::path dumped = scratch / "dom.html";
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = io::runProgram({chromium, "--headless", "--no-sandbox", "--disable-gpu", "--dump-dom", url},
                                {dumped.string(), "/dev/null", {}});
  const double s = secondsSince(t0);
  if (dom) *dom = io::readTextFile(dumped.string());
  return rc == 0 ? s : -1;
}

// The number after "key": in the page's timing line; -1 when absent.
double timing(const std::string& dom, const std::string& key) {
  const auto p = dom.find("&quot;" + key + "&quot;:");
  const auto q = dom.find("\"" + key + "\":");
  const std::size_t at = p != std::string::npos   ? p + key.size() + 13
                         : q != std::string::npos ? q + key.size() + 3
                                                  : 0;
  return at ? std::atof(dom.c_str() + at) : -1;
}

} // namespace

const OptionTable& benchBidsOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench bids";
    t.intro =
        "Seconds per participant of `dtfabric bids` on participants made of the real DWI, and the time to\n"
        "write the group report of a replicated cohort.";
    t.options = {
        sharedDataOption(),
        O::integer("runs", "N", 3, closedRange(1, 50),
                   "participants made of the real DWI, processed one after the other"),
        O::integer("rows", "N", 300, closedRange(1, 100000), "rows of the replicated cohort for the report"),
        O::integer("figure-size", "PX", session::ParticipantOptions{}.figurePx, closedRange(64, 2048),
                   "figure edge (as `dtfabric bids`)"),
        O::flag("json", "one JSON object"),
        O::flag("keep", "keep the scratch dataset and outputs (printed)"),
    };
    return t;
  }();
  return table;
}

namespace {

// What `bench bids` measures.
struct BidsFigures {
  int figurePx = 0, cores = 1, rows = 0;
  std::vector<double> total, fit, check, figures, load; // seconds per run
  double groupSeconds = 0;
  std::size_t htmlBytes = 0;
  std::string chromium; // empty: not on the PATH
  double chromeEmpty = -1, chromeReport = -1, sortMs = -1, detailMs = -1, scriptMs = -1;
  double jobsPerRun = -1;
};

// A BIDS dataset of `runs` participants, each a copy of the real DWI.
void makeCohort(const fs::path& src, const fs::path& bids, int runs) {
  fs::create_directories(bids);
  io::writeTextIfChanged((bids / "dataset_description.json").string(),
                         io::jsonText(nlohmann::ordered_json{{"Name", "bench"}, {"BIDSVersion", "1.8.0"}}, 2) + "\n");
  for (int n = 1; n <= runs; ++n) {
    char sub[16];
    std::snprintf(sub, sizeof sub, "%02d", n);
    const fs::path dir = bids / ("sub-" + std::string(sub)) / "dwi";
    fs::create_directories(dir);
    const std::string stem = "sub-" + std::string(sub) + "_dwi";
    fs::copy_file(src / "dwi.nii.gz", dir / (stem + ".nii.gz"));
    fs::copy_file(src / "dwi.bval", dir / (stem + ".bval"));
    fs::copy_file(src / "dwi.bvec", dir / (stem + ".bvec"));
  }
}

// Each run processed in this process, one after the other; the stage times from its metrics document.
void timeParticipants(const io::BidsDataset& ds, const fs::path& out, BidsFigures& f) {
  session::ParticipantOptions opts;
  opts.figurePx = f.figurePx;
  opts.version = DTF_VERSION;
  opts.fitThreads = f.cores;
  for (const auto& r : ds.runs) {
    const session::RunOutcome o = session::processRun(r, out.string(), opts);
    if (!o.ok) throw InputError("bench bids: " + r.dwi + " failed: " + o.message);
    const std::string doc = session::metricsPath(r, out.string());
    const nlohmann::ordered_json j = io::readJsonFile(doc);
    f.total.push_back(o.seconds);
    f.load.push_back(io::jsonNumber(j, "seconds_load"));
    f.fit.push_back(io::jsonNumber(j, "seconds_fit"));
    f.check.push_back(io::jsonNumber(j, "seconds_check"));
    f.figures.push_back(io::jsonNumber(j, "seconds_figures"));
  }
}

// The group level over the measured rows replicated with distinct names and slightly spread metrics.
void timeGroupReport(const io::BidsDataset& ds, const fs::path& out, BidsFigures& f) {
  std::vector<io::GroupRow> base;
  for (const auto& r : ds.runs)
    base.push_back(session::readGroupRow(r, out.string()));
  std::vector<io::GroupRow> rows;
  for (int n = 0; n < f.rows; ++n) {
    io::GroupRow row = base[static_cast<std::size_t>(n) % base.size()];
    char name[32];
    std::snprintf(name, sizeof name, "sub-%04d_dwi", n + 1);
    row.run = name;
    row.participant = std::string(name).substr(0, 8);
    for (auto& m : row.metrics)
      m *= 1.0 + 0.01 * std::sin(0.7 * n);
    rows.push_back(std::move(row));
  }
  const auto t0 = std::chrono::steady_clock::now();
  io::flagOutliers(rows);
  const std::string tsv = io::groupTsv(rows);
  const std::string html = io::groupReportHtml(rows, "bench cohort", "dtfabric " + std::string(DTF_VERSION));
  io::writeTextIfChanged((out / "group.tsv").string(), tsv);
  io::writeTextIfChanged((out / "group_report.html").string(), html);
  f.groupSeconds = secondsSince(t0);
  f.htmlBytes = html.size();
}

// Headless Chromium loading the report (beside an empty page for its start-up) and the page's own timings.
void timeReportInChromium(const fs::path& out, const fs::path& scratch, BidsFigures& f) {
  f.chromium = io::findOnPath("chromium");
  if (f.chromium.empty()) return;
  io::writeTextIfChanged((out / "empty.html").string(), "<!DOCTYPE html><html><body>x</body></html>\n");
  f.chromeEmpty = chromiumSeconds(f.chromium, "file://" + (out / "empty.html").string(), scratch);
  std::string dom;
  f.chromeReport =
      chromiumSeconds(f.chromium, "file://" + (out / "group_report.html").string() + "#timing", scratch, &dom);
  f.sortMs = timing(dom, "sort_ms");
  f.detailMs = timing(dom, "detail_ms");
  f.scriptMs = timing(dom, "script_ms");
}

// The same runs through the CLI with --jobs (worker processes), all recomputed.
void timeJobs(const fs::path& bids, const fs::path& out, std::size_t runs, BidsFigures& f) {
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = io::runProgram({fs::read_symlink("/proc/self/exe").string(), "bids", bids.string(), out.string(),
                                 "participant", "--force", "--jobs", std::to_string(f.cores), "--figure-size",
                                 std::to_string(f.figurePx)});
  f.jobsPerRun = rc == 0 ? secondsSince(t0) / static_cast<double>(runs) : -1;
}

void printBidsJson(const BidsFigures& f) {
  const nlohmann::ordered_json j = {{"runs", f.total.size()},
                                    {"figure_px", f.figurePx},
                                    {"cores", f.cores},
                                    {"seconds_per_run", median(f.total)},
                                    {"seconds_load", median(f.load)},
                                    {"seconds_fit", median(f.fit)},
                                    {"seconds_check", median(f.check)},
                                    {"seconds_figures", median(f.figures)},
                                    {"first_run_seconds", f.total.front()},
                                    {"report_rows", f.rows},
                                    {"report_seconds", f.groupSeconds},
                                    {"report_bytes", f.htmlBytes},
                                    {"chromium_empty_seconds", f.chromeEmpty},
                                    {"chromium_report_seconds", f.chromeReport},
                                    {"sort_ms", f.sortMs},
                                    {"detail_ms", f.detailMs},
                                    {"script_ms", f.scriptMs},
                                    {"jobs", f.cores},
                                    {"seconds_per_run_jobs", f.jobsPerRun}};
  std::printf("%s\n", io::jsonText(j).c_str());
}

void printBidsTable(const BidsFigures& f) {
  std::printf("participant level on the real DWI (72x72x39x21), %zu runs in this process, %.0f cores, "
              "figures %d px:\n",
              f.total.size(), static_cast<double>(f.cores), f.figurePx);
  // The first run also pays for the GL context and the noise tile; the median is the steady state.
  std::printf("  seconds per run (median)  %.2f   (first run %.2f: GL context and noise tile)\n", median(f.total),
              f.total.front());
  std::printf("    load %.2f  fit %.2f  check %.2f  figures (4%s) %.2f\n", median(f.load), median(f.fit),
              median(f.check), "", median(f.figures));
  std::printf("group level over %d replicated rows: %.3f s (outliers, group.tsv, %zu kB of HTML)\n", f.rows,
              f.groupSeconds, f.htmlBytes / 1024);
  if (f.chromeReport >= 0)
    std::printf("headless chromium --dump-dom: report %.2f s, an empty page %.2f s (start-up): load %.2f s\n",
                f.chromeReport, f.chromeEmpty, f.chromeReport - f.chromeEmpty);
  else
    std::printf("chromium: %s\n", f.chromium.empty() ? "not on the PATH (not measured)" : "failed");
  if (f.sortMs >= 0)
    std::printf("  in the page: script ran %.0f ms after navigation; sort by a metric %.1f ms; open a run "
                "%.1f ms\n",
                f.scriptMs, f.sortMs, f.detailMs);
  std::printf("dtfabric bids --jobs %d (worker processes, %zu runs, all recomputed): %.2f s per run\n", f.cores,
              f.total.size(), f.jobsPerRun);
}

} // namespace

int benchBids(const CommandArgs& argv) {
  ParsedOptions args(benchBidsOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  BidsFigures f;
  const auto data = findSharedDataDir(args.get("data"));
  const int runsWanted = args.integer("runs");
  f.rows = args.integer("rows");
  f.figurePx = args.integer("figure-size");
  const bool json = args.flag("json"), keep = args.flag("keep");
  args.finish();
  if (!data || !fs::exists(*data / "iu_prisma_dwi" / "dwi.nii.gz"))
    throw InputError("bench bids needs the real DWI (../shared/data/iu_prisma_dwi; give --data DIR)");
  f.cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  char tmpl[] = "/tmp/dtfabric_bench_bids_XXXXXX";
  if (!::mkdtemp(tmpl)) throw InputError("cannot make a scratch folder in /tmp");
  const fs::path scratch = tmpl, bids = scratch / "bids", out = scratch / "out";
  makeCohort(*data / "iu_prisma_dwi", bids, runsWanted);
  const io::BidsDataset ds = io::scanBidsDataset(bids.string());
  fs::create_directories(out);
  timeParticipants(ds, out, f);
  timeGroupReport(ds, out, f);
  timeReportInChromium(out, scratch, f);
  timeJobs(bids, scratch / "out_jobs", ds.runs.size(), f);

  if (json)
    printBidsJson(f);
  else
    printBidsTable(f);
  if (keep)
    std::fprintf(stderr, "kept %s\n", scratch.string().c_str());
  else
    fs::remove_all(scratch);
  return 0;
}

} // namespace dtf::app
