// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench select`: ROI selection at whole-brain scale. A synthetic tractogram (default 10 M
// streamlines of 50 points 2 mm apart, smooth random walks inside a brain-sized ellipsoid) is indexed
// (surfaces/selection) and queried with spheres of 5-15 mm; the real tracts of the shared data are selected
// with the spheres of their corticospinal tracts; and, with MRtrix's tckedit on the PATH, the same sphere
// selection of a 1 M-streamline .tck runs as `dtfabric select` and as `tckedit` in the same run (whole
// commands, read to written, alternating), as the peer. The viewer's region move is timed on the synthetic
// set as `selection_update_ms`: a sphere moved, the selection recomputed with the index (the ROI worker's
// call), the drawn subset and its display prepared, uploaded and drawn once under the viewer's frame budget
// in a headless GL context (and `selection_update_full_ms` with every display point drawn instead).
#include "app/bench/bench.h"
#include "io/formats/json.h"
#include "io/formats/process.h"
#include "io/formats/tracts.h"
#include "io/model/error.h"
#include "io/model/huge_pages.h"
#include "render/camera.h"
#include "render/gl_context.h"
#include "render/gl_objects.h"
#include "render/reference/scenes.h"
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "surfaces/selection/tract_selection.h"
#include "ui/session/roi_worker.h"
#include "ui/session/tract_files.h"
#include "ui/session/tract_overlay.h"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <epoxy/gl.h>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <thread>
#include <unistd.h>

namespace dtf::app {

const OptionTable& benchSelectOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench select";
    t.intro =
        "ROI selection at whole-brain scale: builds the spatial index of a synthetic tractogram (N streamlines\n"
        "of P points 2 mm apart in a brain-sized ellipsoid), times sphere queries of 5-15 mm (index, then the\n"
        "walk of the survivors), selects the real tracts of the shared data, and, with MRtrix's tckedit on the\n"
        "PATH (Debian package mrtrix3), times `dtfabric select` against `tckedit` on the same sphere of a .tck\n"
        "of the first --peer-streamlines synthetic streamlines (whole commands, alternating).";
    t.options = {
        O::integer("streamlines", "N", 10000000, closedRange(1000, 100000000), "synthetic streamlines"),
        O::integer("points", "P", 50, closedRange(2, 1000), "points per synthetic streamline"),
        O::integer("queries", "Q", 21, closedRange(1, 1000), "sphere queries (the median is reported)"),
        O::integer("peer-streamlines", "M", 1000000, closedRange(0, 100000000),
                   "streamlines of the .tck both commands select from (0: no peer run)"),
        O::integer("repeat", "R", 3, closedRange(1, 100), "runs of each whole command (medians)"),
        O::number("cell", "MM", 0, atLeast(0), "the index's grid cell (0: from the streamlines' step, at least 4 mm)")
            .measuredIn("mm"),
        O::integer("threads", "T", 0, atLeast(0), "worker threads").defaultSays("all cores"),
        O::text("save", "FILE",
                "also write the synthetic tractogram there (.trx, .tck, .trk, ...; an existing file is kept), e.g. "
                "to open 10 M streamlines in the viewer"),
        O::flag("json", "one JSON object"),
        sharedDataOption(),
    };
    return t;
  }();
  return table;
}

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double peakRssGb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / (1024.0 * 1024.0); // kB -> GB
}

// Counter-based random numbers: the value depends only on (line, k), so generation is parallel and
// reproducible.
float hashUnit(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull);
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 29;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 32;
  return static_cast<float>(x & 0xFFFFFF) / static_cast<float>(0x1000000);
}

const glm::vec3 kHalfAxes(70.0f, 85.0f, 60.0f); // a brain-sized ellipsoid, mm

bool insideBrain(const glm::vec3& p) {
  const glm::vec3 q = p / kHalfAxes;
  return glm::dot(q, q) <= 1.0f;
}

// N streamlines of P points, 2 mm apart: smooth random walks that turn back at the ellipsoid's surface.
Polylines syntheticTractogram(std::size_t n, int points, int threads) {
  Polylines lines;
  // Huge pages: the queries read the positions at random, and 4 KiB pages make that a TLB miss each time.
  lines.points.reserve(n * static_cast<std::size_t>(points));
  adviseHugePages(lines.points.data(), n * static_cast<std::size_t>(points) * sizeof(glm::vec3));
  lines.points.resize(n * static_cast<std::size_t>(points));
  lines.offsets.resize(n + 1);
  const int T = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto work = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      glm::vec3 p;
      int tries = 0;
      do {
        p = (glm::vec3(hashUnit(i, 1000 + tries), hashUnit(i, 2000 + tries), hashUnit(i, 3000 + tries)) * 2.0f -
             1.0f) * kHalfAxes;
        ++tries;
      } while (!insideBrain(p) && tries < 64);
      glm::vec3 d = glm::normalize(glm::vec3(hashUnit(i, 1), hashUnit(i, 2), hashUnit(i, 3)) - 0.5f + 1e-3f);
      glm::vec3* out = lines.points.data() + i * static_cast<std::size_t>(points);
      for (int k = 0; k < points; ++k) {
        out[k] = p;
        const glm::vec3 bend(hashUnit(i, 10 + 3 * static_cast<std::uint64_t>(k)) - 0.5f,
                             hashUnit(i, 11 + 3 * static_cast<std::uint64_t>(k)) - 0.5f,
                             hashUnit(i, 12 + 3 * static_cast<std::uint64_t>(k)) - 0.5f);
        d = glm::normalize(d + 0.35f * bend);
        if (!insideBrain(p + 2.0f * d)) d = -d;
        p += 2.0f * d;
      }
      lines.offsets[i] = static_cast<std::uint32_t>(i * static_cast<std::size_t>(points));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < T; ++t)
    pool.emplace_back(work, n * static_cast<std::size_t>(t) / static_cast<std::size_t>(T),
                      n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(T));
  work(0, n / static_cast<std::size_t>(T));
  for (auto& th : pool)
    th.join();
  lines.offsets[n] = static_cast<std::uint32_t>(n * static_cast<std::size_t>(points));
  return lines;
}

surfaces::RegionSet sphereSet(const glm::dvec3& c, double r) {
  surfaces::Region s;
  s.shape = surfaces::RegionShape::Sphere;
  s.centre = c;
  s.radius = r;
  s.name = "sphere";
  surfaces::RegionSet set;
  set.regions = {s};
  return set;
}

struct Query {
  double ms = 0;
  std::size_t selected = 0, candidates = 0;
};

// A whole command run `repeat` times; wall and CPU seconds (medians).
struct CommandTime {
  bool ran = false;
  double wall = 0, cpu = 0;
  int exitCode = 0;
};

CommandTime timeCommand(const std::vector<std::string>& argv) {
  CommandTime t;
  const double c0 = childCpuSeconds();
  const auto t0 = Clock::now();
  t.exitCode = io::runProgram(argv);
  t.wall = since(t0);
  t.cpu = childCpuSeconds() - c0;
  t.ran = t.exitCode == 0;
  return t;
}

// The streamline count a .tck header declares (-1 when unreadable).
long long tckCount(const std::string& path) {
  try {
    io::TckInfo info;
    io::readTck(path, &info);
    return info.declaredCount;
  } catch (const Error&) {
    return -1;
  }
}

} // namespace

int benchSelect(const CommandArgs& argv) {
  ParsedOptions args(benchSelectOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const auto n = static_cast<std::size_t>(args.integer("streamlines"));
  const int points = args.integer("points");
  const int queries = args.integer("queries");
  const auto peerN = static_cast<std::size_t>(args.integer("peer-streamlines"));
  const int repeat = args.integer("repeat");
  const int threads = args.integer("threads");
  const double cellMm = args.number("cell");
  const bool json = args.flag("json");
  const auto dataArg = args.get("data");
  const auto savePath = args.get("save");
  args.finish();
  if (savePath && std::filesystem::exists(*savePath))
    throw UsageError("bench select --save: " + *savePath + " exists (it is kept; choose another path)");
  std::vector<std::string> notes;

  // The peer first, while this process holds little memory: the same sphere on a .tck of the first peerN
  // synthetic streamlines, whole commands.
  CommandTime ours, peer;
  std::vector<double> oursWall, oursCpu, peerWall, peerCpu;
  long long oursCount = -1, peerCount = -1;
  std::string peerNote;
  const std::string tckedit = io::findOnPath("tckedit");
  if (peerN == 0)
    peerNote = "no peer run (--peer-streamlines 0)";
  else if (tckedit.empty())
    peerNote = "MRtrix tckedit is not on the PATH (Debian package mrtrix3); no comparison";
  else {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("dtf_bench_select_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string in = (dir / "whole_brain.tck").string(), a = (dir / "ours.tck").string(),
                      b = (dir / "tckedit.tck").string();
    io::writeTck(in, syntheticTractogram(peerN, points, threads)); // the first peerN of the large set
    const std::string exe = fs::read_symlink("/proc/self/exe").string();
    const std::string sphere = "0,0,0,10";
    for (int r = 0; r < repeat; ++r) {
      ours = timeCommand({exe, "select", in, "-o", a, "--include", sphere, "--force"});
      peer = timeCommand({tckedit, in, b, "-include", sphere, "-force", "-quiet"});
      if (!ours.ran || !peer.ran) break;
      oursWall.push_back(ours.wall);
      oursCpu.push_back(ours.cpu);
      peerWall.push_back(peer.wall);
      peerCpu.push_back(peer.cpu);
    }
    if (ours.ran && peer.ran) {
      oursCount = tckCount(a);
      peerCount = tckCount(b);
    } else {
      peerNote = ours.ran ? "tckedit failed (exit status " + std::to_string(peer.exitCode) + ")"
                          : "dtfabric select failed (exit status " + std::to_string(ours.exitCode) + ")";
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  const bool peerRan = !oursWall.empty();

  // The synthetic whole-brain tractogram, its index and the sphere queries.
  auto t0 = Clock::now();
  Polylines lines = syntheticTractogram(n, points, threads);
  const double generateS = since(t0);
  const double positionsGb = static_cast<double>(lines.points.size() * sizeof(glm::vec3)) / (1024.0 * 1024 * 1024);
  double saveS = -1;
  if (savePath) {
    // A 1 mm grid over the ellipsoid: the reference .trk and .trx need.
    const Grid reference = Grid::fromAffine(glm::ivec3(2.0f * kHalfAxes) + 1,
                                            glm::translate(glm::dmat4(1.0), -glm::dvec3(kHalfAxes)));
    t0 = Clock::now();
    session::writeTracts(*savePath, lines, &reference);
    saveS = since(t0);
  }
  const surfaces::TractView view = surfaces::viewOf(lines);
  t0 = Clock::now();
  const surfaces::TractIndex index(view, cellMm, threads);
  const double buildS = since(t0);
  std::vector<Query> qs;
  std::vector<double> ms;
  for (int q = 0; q < queries; ++q) {
    // Centres inside the inner part of the ellipsoid, radii 5..15 mm.
    glm::dvec3 c;
    int tries = 0;
    do {
      c = glm::dvec3((glm::vec3(hashUnit(7777 + q, tries), hashUnit(8888 + q, tries), hashUnit(9999 + q, tries)) *
                          2.0f - 1.0f) * kHalfAxes * 0.8f);
      ++tries;
    } while (!insideBrain(glm::vec3(c)) && tries < 64);
    const double r = 5.0 + 10.0 * static_cast<double>(q) / std::max(1, queries - 1);
    const surfaces::RegionTester tester(sphereSet(c, r));
    surfaces::SelectionStats st;
    const auto tq = Clock::now();
    const auto kept = surfaces::selectLines(view, tester, &index, threads, &st);
    Query x;
    x.ms = 1000.0 * since(tq);
    x.selected = kept.size();
    x.candidates = st.candidates;
    qs.push_back(x);
    ms.push_back(x.ms);
  }
  const double queryMs = median(ms);
  // One walk without the index, for scale.
  t0 = Clock::now();
  const surfaces::RegionTester middle(sphereSet(glm::dvec3(0.0), 10.0));
  const auto walked = surfaces::selectLines(view, middle, nullptr, threads);
  const double walkMs = 1000.0 * since(t0);
  const double peakGb = peakRssGb();

  // The viewer's region move, as the viewer runs it from a drag to the redrawn overlay (there on the ROI
  // worker, the tract worker and the UI thread; here one after the other): a 10 mm sphere moved 2 mm at a
  // time, the selection recomputed with the index, the selected streamlines drawn (the others hidden) on an
  // axial slice with a 3 mm slab: their display subset (render::decimateForDisplay of the kept lines, what
  // the ROI worker makes), its levels of detail, the upload, and the first frame the viewer shows: the
  // level of detail its frame budget picks (render::TractBudget, learnt over the moves), finished
  // (glFinish), at 512x512 pixels: selection_update_ms. The still frame that follows draws every display
  // point: selection_update_full_ms (the same steps with that draw instead of the budgeted one).
  double updateMs = -1, updateMsMax = -1, updateFullMs = -1;
  // select, display subset, levels, upload, budgeted draw, full draw
  std::array<double, 6> updateParts{-1, -1, -1, -1, -1, -1};
  std::size_t updateSelected = 0, updateShownLines = 0, updateShownPoints = 0;
  double nearUpdateMs = -1, nearUpdateMsMax = -1, nearUpdateFullMs = -1;
  std::size_t nearSelected = 0, nearQuickPoints = 0, nearFullPoints = 0;
  try {
    render::GlContext::headless();
    render::TractRenderer tr;
    const int size = 512;
    render::Texture colour = render::Texture::create2D(GL_RGBA8, size, size);
    render::Texture depth = render::Texture::create2D(GL_DEPTH_COMPONENT32F, size, size);
    render::Framebuffer fbo = render::createFramebuffer();
    render::attachTargets(fbo, {&colour}, &depth);
    const glm::vec3 lo = -kHalfAxes, hi = kHalfAxes;
    const render::Camera cam = render::Camera::standard(render::StandardView::Axial, lo, hi, 1.0);
    const render::FrameView fv = render::FrameView::make(cam, {size, size}, 0, lo, hi);
    render::TractStyle style;
    style.plane = glm::vec4(0, 0, 1, 0);
    style.slabMm = 3.0f;
    const std::shared_ptr<const Polylines> shared(std::shared_ptr<const Polylines>(), &lines); // not owned
    std::vector<double> ums, fullMs;
    std::array<std::vector<double>, 6> parts;
    render::TractBudget budget; // the viewer's frame budget: a moving frame draws what fits in its target
    const float clearColour[4] = {0, 0, 0, 1}, one = 1.0f;
    auto clear = [&] {
      glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, clearColour);
      glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &one);
      glFinish();
    };
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    for (int k = 0; k <= 10; ++k) {
      session::RoiJob job;
      job.tracts = shared;
      job.set = sphereSet(glm::dvec3(-10.0 + 2.0 * k, 0, 0), 10.0);
      clear();
      const auto t0 = Clock::now();
      const session::RoiResult r = session::RoiWorker::run(job, &index);
      const auto t1 = Clock::now();
      const Polylines subset = render::decimateForDisplay(lines, *r.lines); // the ROI worker's subset
      const auto t2 = Clock::now();
      const render::DisplayTracts display = session::tractOverlayDisplay(subset);
      const auto t3 = Clock::now();
      tr.upload(display);
      glFinish();
      const auto t4 = Clock::now();
      glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
      const render::TractBudget::Choice choice = budget.choose(tr);
      tr.draw(fv, style, choice.level, 0, choice.segments);
      glFinish();
      const auto t5 = Clock::now();
      budget.measured(choice.level, choice.segments, ms(t4, t5));
      clear();
      const auto t6 = Clock::now();
      tr.draw(fv, style); // every display point: the still frame
      glFinish();
      const auto t7 = Clock::now();
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      if (k > 0) { // the first move warms the caches and the GL objects
        ums.push_back(ms(t0, t5));
        fullMs.push_back(ms(t0, t4) + ms(t6, t7));
        const double p[6] = {ms(t0, t1), ms(t1, t2), ms(t2, t3), ms(t3, t4), ms(t4, t5), ms(t6, t7)};
        for (int i = 0; i < 6; ++i)
          parts[static_cast<std::size_t>(i)].push_back(p[i]);
      }
      updateSelected = r.lines->size();
      updateShownLines = display.lines;
      updateShownPoints = display.points.size();
    }
    render::checkGl("bench select: the overlay update");
    // The same moves near a curved surface (an ellipsoid of 0.6 the brain's half axes, 3 mm rule), seen from
    // above: the ROI worker's subset of whole streamlines, the quick near-surface pass the viewer draws first
    // (kNearSurfaceQuickPointCap), its display, upload and budgeted frame: selection_update_near_ms; then
    // the full pass (kNearSurfacePointCap) that follows, to its still frame: selection_update_near_full_ms.
    Mesh ellipsoid = render::reference::uvSphere(glm::dvec3(0.0), 1.0, 96, 192);
    for (glm::vec3& p : ellipsoid.positions)
      p *= 0.6f * kHalfAxes;
    const render::Camera top = render::Camera::standard(render::StandardView::Superior, lo, hi, 1.0);
    const render::FrameView tv = render::FrameView::make(top, {size, size}, 0, lo, hi);
    const render::TractStyle free;
    std::vector<double> nearMs, nearFullMs;
    render::TractBudget nearBudget;
    for (int k = 0; k <= 6; ++k) {
      session::RoiJob job;
      job.tracts = shared;
      job.set = sphereSet(glm::dvec3(-10.0 + 2.0 * k, 0, 36), 10.0); // across the ellipsoid's top
      clear();
      const auto t0 = Clock::now();
      const session::RoiResult r = session::RoiWorker::run(job, &index);
      const Polylines whole = render::decimateForDisplay(lines, *r.lines, session::kNearSurfacePointCap,
                                                         render::kWholeDisplayLines);
      const session::TractSelection quick =
          session::selectTracts(whole, ellipsoid, 3.0, nullptr, session::kNearSurfaceQuickPointCap);
      tr.upload(session::tractOverlayDisplay(quick.near));
      glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
      const render::TractBudget::Choice choice = nearBudget.choose(tr);
      tr.draw(tv, free, choice.level, 0, choice.segments);
      glFinish();
      const auto t1 = Clock::now();
      nearBudget.measured(choice.level, choice.segments, ms(t0, t1)); // not only the draw: a coarse budget
      const session::TractSelection full = session::selectTracts(whole, ellipsoid, 3.0);
      tr.upload(session::tractOverlayDisplay(full.near));
      clear();
      glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
      tr.draw(tv, free);
      glFinish();
      const auto t2 = Clock::now();
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      if (k > 0) {
        nearMs.push_back(ms(t0, t1));
        nearFullMs.push_back(ms(t0, t2));
      }
      nearSelected = r.lines->size();
      nearQuickPoints = quick.near.points.size();
      nearFullPoints = full.near.points.size();
    }
    render::checkGl("bench select: the overlay update near a surface");
    nearUpdateMs = median(nearMs);
    nearUpdateMsMax = *std::max_element(nearMs.begin(), nearMs.end());
    nearUpdateFullMs = median(nearFullMs);
    updateMs = median(ums);
    updateMsMax = *std::max_element(ums.begin(), ums.end());
    updateFullMs = median(fullMs);
    for (std::size_t i = 0; i < 6; ++i)
      updateParts[i] = median(parts[i]);
  } catch (...) {
    notes.push_back("no selection_update_ms: " + currentExceptionMessage());
  }

  // The real tracts: the corticospinal tracts' spheres on the deterministic tracks of the bundled brain.
  double realIndexMs = -1, realQueryMs = -1;
  std::size_t realLines = 0, realSelected = 0;
  const auto data = findSharedDataDir(dataArg);
  const auto realPath = data ? *data / "iu_prisma_dwi/derived/tracks_det.tck" : std::filesystem::path();
  if (data && std::filesystem::exists(realPath)) {
    const Polylines real = io::readTck(realPath.string());
    realLines = real.lineCount();
    const surfaces::TractView rv = surfaces::viewOf(real);
    t0 = Clock::now();
    const surfaces::TractIndex ri(rv, 0.0, threads);
    realIndexMs = 1000.0 * since(t0);
    // Two spheres along the right corticospinal tract: at voxel (30, 34, 15) and in the corona radiata.
    surfaces::RegionSet set = sphereSet(glm::dvec3(18, 3.7, 21.6), 6);
    set.regions.push_back(sphereSet(glm::dvec3(20, 0, 45), 10).regions.front());
    const surfaces::RegionTester rt(set);
    std::vector<double> rms;
    for (int q = 0; q < 5; ++q) {
      t0 = Clock::now();
      realSelected = surfaces::selectLines(rv, rt, &ri, threads).size();
      rms.push_back(1000.0 * since(t0));
    }
    realQueryMs = median(rms);
  } else {
    notes.push_back("the shared data's tracks_det.tck is missing: no real-tract figures");
  }

  const double ratio = peerRan ? median(peerWall) / median(oursWall) : -1;
  if (json) {
    nlohmann::ordered_json j = {
        {"streamlines", n},
        {"points", lines.points.size()},
        {"index_build_s", buildS},
        {"sphere_query_ms", queryMs},
        {"sphere_query_ms_max", *std::max_element(ms.begin(), ms.end())},
        {"selection_update_ms", updateMs},
        {"selection_update_ms_max", updateMsMax},
        {"selection_update_full_ms", updateFullMs},
        {"selection_update_selected", updateSelected},
        {"selection_update_shown_lines", updateShownLines},
        {"selection_update_shown_points", updateShownPoints},
        {"selection_update_parts_ms",
         {{"select", updateParts[0]},
          {"display_subset", updateParts[1]},
          {"levels", updateParts[2]},
          {"upload", updateParts[3]},
          {"budgeted_draw", updateParts[4]},
          {"full_draw", updateParts[5]}}},
        {"selection_update_near_ms", nearUpdateMs},
        {"selection_update_near_ms_max", nearUpdateMsMax},
        {"selection_update_near_full_ms", nearUpdateFullMs},
        {"selection_update_near_selected", nearSelected},
        {"selection_update_near_quick_points", nearQuickPoints},
        {"selection_update_near_full_points", nearFullPoints},
        {"queries", queries},
        {"query_selected_median", qs[qs.size() / 2].selected},
        {"walk_without_index_ms", walkMs},
        {"walk_selected", walked.size()},
        {"generate_s", generateS},
        {"save_s", saveS},
        {"index_bytes", index.bytes()},
        {"cell_mm", index.cellMm()},
        {"positions_gb", positionsGb},
        {"peak_rss_gb", peakGb},
        {"peak_over_positions", peakGb / positionsGb},
        {"threads", threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())},
        {"real_streamlines", realLines},
        {"real_index_ms", realIndexMs},
        {"real_query_ms", realQueryMs},
        {"real_selected", realSelected},
        {"peer", "MRtrix tckedit -include (sphere)"},
        {"peer_ran", peerRan},
        {"peer_streamlines", peerRan ? peerN : 0},
        {"peer_s", peerRan ? median(peerWall) : -1},
        {"peer_cpu_s", peerRan ? median(peerCpu) : -1},
        {"peer_select_s", peerRan ? median(oursWall) : -1},
        {"peer_select_cpu_s", peerRan ? median(oursCpu) : -1},
        {"peer_speedup", ratio},
        {"peer_selected", peerCount},
        {"peer_select_selected", oursCount},
        {"load_average", loadAverage()}};
    if (!peerNote.empty()) j["peer_note"] = peerNote;
    if (!notes.empty()) j["notes"] = notes;
    std::printf("%s\n", io::jsonText(j).c_str());
    return 0;
  }
  std::printf("ROI selection on a synthetic whole-brain tractogram: %zu streamlines, %zu points (%.2f GB of "
              "positions), generated in %.1f s\n",
              n, lines.points.size(), positionsGb, generateS);
  std::printf("  index: built in %.2f s, %.2f GB (cell %.1f mm, %zu chunks)\n", buildS,
              static_cast<double>(index.bytes()) / (1024.0 * 1024 * 1024), index.cellMm(), index.chunkCount());
  std::printf("  sphere query (5-15 mm, index + walk of the survivors): median %.1f ms, max %.1f ms over %d "
              "(median %zu selected)\n",
              queryMs, *std::max_element(ms.begin(), ms.end()), queries, qs[qs.size() / 2].selected);
  std::printf("  the same query walking every streamline: %.0f ms (%zu selected)\n", walkMs, walked.size());
  std::printf("  viewer region move (10 mm sphere moved 2 mm, %zu selected, %zu lines / %zu points drawn): "
              "to the first frame (budgeted) median %.1f ms, max %.1f ms; to the full still frame %.1f ms\n"
              "    select %.1f, display subset %.1f, levels %.1f, upload %.1f, budgeted draw %.1f, full draw "
              "%.1f ms\n",
              updateSelected, updateShownLines, updateShownPoints, updateMs, updateMsMax, updateFullMs,
              updateParts[0], updateParts[1], updateParts[2], updateParts[3], updateParts[4], updateParts[5]);
  std::printf("  the same move near a curved surface (ellipsoid, 3 mm rule, %zu selected): quick pass drawn "
              "(%zu points near it) median %.1f ms, max %.1f ms; full pass drawn (%zu points) %.1f ms\n",
              nearSelected, nearQuickPoints, nearUpdateMs, nearUpdateMsMax, nearFullPoints, nearUpdateFullMs);
  if (savePath) std::printf("  written to %s in %.1f s\n", savePath->c_str(), saveS);
  std::printf("  peak memory %.2f GB = %.2fx the positions\n", peakGb, peakGb / positionsGb);
  if (realLines)
    std::printf("  real tracts (tracks_det.tck, %zu streamlines): index %.2f ms, two CST spheres %.3f ms, %zu "
                "selected\n",
                realLines, realIndexMs, realQueryMs, realSelected);
  if (peerRan)
    std::printf("  peer on %zu streamlines, sphere 0,0,0,10, whole commands (median of %d): dtfabric select %.2f s "
                "(CPU %.2f s), tckedit %.2f s (CPU %.2f s) -> %.2fx; selected %lld and %lld\n",
                peerN, repeat, median(oursWall), median(oursCpu), median(peerWall), median(peerCpu),
                ratio, oursCount, peerCount);
  else
    std::printf("  peer: %s\n", peerNote.c_str());
  for (const auto& note : notes)
    std::printf("  note: %s\n", note.c_str());
  return 0;
}

} // namespace dtf::app
