// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench view`: frame times of the viewer's scene (app/viewer/viewer.h, the code the window runs) while
// the FA threshold is swept and while the camera rotates, on the real brain's FA isosurface. Runs in the
// headless context: the window adds only ImGui and a blit.
#include "app/bench/bench.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "app/viewer/viewer.h"
#include "io/model/error.h"
#include "render/gl_context.h"
#include "io/formats/json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <epoxy/gl.h>
#include <nlohmann/json.hpp>
#include <numeric>
#include <thread>

namespace dtf::app {

namespace {

using Clock = std::chrono::steady_clock;

struct Stats {
  double mean = 0, median = 0, p95 = 0, fps = 0;
  int frames = 0;
};

Stats stats(std::vector<double> ms) {
  Stats s;
  s.frames = static_cast<int>(ms.size());
  if (ms.empty()) return s;
  s.mean = std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size();
  std::sort(ms.begin(), ms.end());
  s.median = ms[ms.size() / 2];
  s.p95 = ms[std::min(ms.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * ms.size())) - 1)];
  s.fps = 1000.0 / s.mean;
  return s;
}

void waitSettled(ViewerScene& scene, double seconds) {
  const auto t0 = Clock::now();
  while (!scene.settled()) {
    scene.update();
    if (std::chrono::duration<double>(Clock::now() - t0).count() > seconds)
      throw Error("bench view: the scene did not settle within " + std::to_string(seconds) + " s");
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  scene.update();
  if (!scene.state().errorChain.empty()) throw InputError("bench view: " + scene.state().errorChain.back());
}

} // namespace

const OptionTable& benchViewOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench view";
    t.intro =
        "Frame times of the viewer scene (headless) while sweeping the FA threshold and while rotating\n"
        "the FA isosurface of the shared brain (iu_prisma_dwi/derived/dti_tensor.nii.gz), then while\n"
        "rotating it with tracts within 3 mm drawn over it.";
    t.options = {
        sharedDataOption(),
        O::text("input", "TENSOR", "the tensor volume (default the shared brain)"),
        O::text("tracts", "FILE", "tracts drawn over the surface (default the shared tracks_det.tck)"),
        O::flag("no-tracts", "no tract overlay case"),
        O::text("size", "WxH", "image size", "1024x768").checkedBy(checkSize),
        O::integer("frames", "N", 240, closedRange(10, 100000), "frames per case"),
        O::flag("json", "one JSON object"),
    };
    return t;
  }();
  return table;
}

namespace {

// What `bench view` measures.
struct ViewFigures {
  std::string input;
  int width = 0, height = 0;
  double loadMs = 0;
  std::size_t triangles = 0;
  std::vector<double> sweepMs, rotateMs, rotateFullMs, rotateTractsMs;
  unsigned long long meshesShown = 0;
  double sweepSeconds = 0;
  int stillFrames = 0;
  double stillMs = 0;
  render::PassTimes passes;
  double tractsReadyMs = 0, tractsStillMs = 0;
  int tractsStillFrames = 0;
  std::size_t tractPoints = 0, tractsShown = 0;
};

// The viewer's scene driven like the window loop, without ImGui.
class ViewBench {
public:
  ViewBench(int width, int height, int frames) : scene_("fa=0.25"), width_(width), height_(height), frames_(frames) {}

  double load(const std::string& input) {
    const auto t0 = Clock::now();
    scene_.apply(session::LoadFile{input, "auto"});
    waitSettled(scene_, 300);
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }

  // One pass of the window loop: take worker results, render what changed. Like the window under vsync, a
  // loop iteration takes at least kVsyncMs.
  double frame() {
    constexpr double kVsyncMs = 1000.0 / 60.0;
    const auto t0 = Clock::now();
    scene_.update();
    scene_.render(width_, height_);
    glFinish();
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (ms < kVsyncMs) {
      std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(kVsyncMs - ms));
      ms = kVsyncMs;
    }
    scene_.setFrameMs(ms);
    return ms;
  }

  void converge(int maxFrames) {
    for (int i = 0; i < maxFrames && !scene_.converged(); ++i)
      frame();
  }

  // The slider moves every frame, as when dragged; extraction runs on the worker meanwhile and each new
  // surface restarts the fabric (interactive, then still refinement).
  void sweep(ViewFigures& f) {
    const auto meshesBefore = scene_.meshSerial();
    const auto t0 = Clock::now();
    for (int i = 0; i < frames_; ++i) {
      const double phase = static_cast<double>(i % 120) / 120.0;
      scene_.apply(session::SetFaThreshold{0.15 + 0.30 * (phase < 0.5 ? 2 * phase : 2 - 2 * phase)});
      f.sweepMs.push_back(frame());
    }
    f.sweepSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    f.meshesShown = static_cast<unsigned long long>(scene_.meshSerial() - meshesBefore);
    waitSettled(scene_, 120);
  }

  // A drag every frame.
  std::vector<double> rotate() {
    std::vector<double> ms;
    for (int i = 0; i < frames_; ++i) {
      scene_.apply(session::Rotate{6.0, 2.0});
      ms.push_back(frame());
    }
    return ms;
  }

  // Frames until the fabric converges after the camera stops.
  void still(int maxFrames, int& frames, double& ms) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    while (!scene_.converged() && frames < maxFrames) {
      ms += frame();
      ++frames;
    }
  }

  // GPU pass times of one full-size interactive frame.
  render::PassTimes passTimes() {
    render::FabricRenderer& full = scene_.paneRenderer(0);
    full.setTiming(true);
    scene_.setInteractiveScale(1.0);
    scene_.redraw();
    frame();
    const render::PassTimes pt = full.lastTimes();
    full.setTiming(false);
    return pt;
  }

  // The time to select the tracts within 3 mm of the surface (worker), then rotating with them drawn through
  // the budgeted tract layer, interactive frames at the adaptive size.
  void tracts(const std::string& path, ViewFigures& f) {
    scene_.setInteractiveScale(0.5); // as in the first rotation
    const auto t0 = Clock::now();
    scene_.apply(session::LoadTracts{path});
    waitSettled(scene_, 300);
    f.tractsReadyMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    f.tractPoints = scene_.state().tractPoints;
    f.tractsShown = scene_.state().tractsShownPoints;
    converge(300);
    f.rotateTractsMs = rotate();
    still(1000, f.tractsStillFrames, f.tractsStillMs);
  }

  ViewerScene& scene() { return scene_; }

private:
  ViewerScene scene_;
  int width_, height_, frames_;
};

void printViewJson(const ViewFigures& f, const std::string& gl) {
  const Stats sw = stats(f.sweepMs), ro = stats(f.rotateMs), rf = stats(f.rotateFullMs), rt = stats(f.rotateTractsMs);
  const render::PassTimes& pt = f.passes;
  using Json = nlohmann::ordered_json;
  const Json j = {
      {"input", f.input},
      {"width", f.width},
      {"height", f.height},
      {"load_ms", f.loadMs},
      {"triangles", f.triangles},
      {"sweep",
       {{"frames", sw.frames},
        {"mean_ms", sw.mean},
        {"median_ms", sw.median},
        {"p95_ms", sw.p95},
        {"fps", sw.fps},
        {"surfaces_shown", f.meshesShown},
        {"surfaces_per_s", f.meshesShown / f.sweepSeconds}}},
      {"rotate",
       {{"frames", ro.frames}, {"mean_ms", ro.mean}, {"median_ms", ro.median}, {"p95_ms", ro.p95}, {"fps", ro.fps}}},
      {"rotate_full_size", {{"mean_ms", rf.mean}, {"median_ms", rf.median}, {"p95_ms", rf.p95}, {"fps", rf.fps}}},
      {"passes_ms",
       {{"projection", pt.projection},
        {"silhouette", pt.silhouette},
        {"advection", pt.advection},
        {"composite", pt.composite}}},
      {"still", {{"frames", f.stillFrames}, {"ms", f.stillMs}}},
      {"tracts",
       {{"points", f.tractPoints},
        {"shown", f.tractsShown},
        {"load_select_ms", f.tractsReadyMs},
        {"rotate_mean_ms", rt.mean},
        {"rotate_median_ms", rt.median},
        {"rotate_p95_ms", rt.p95},
        {"rotate_fps", rt.fps},
        {"still_frames", f.tractsStillFrames},
        {"still_ms", f.tractsStillMs}}},
      {"load_average", loadAverage()},
      {"gl", gl}};
  std::printf("%s\n", io::jsonText(j).c_str());
}

void printViewTable(const ViewFigures& f, const std::string& gl) {
  const Stats sw = stats(f.sweepMs), ro = stats(f.rotateMs), rf = stats(f.rotateFullMs), rt = stats(f.rotateTractsMs);
  const render::PassTimes& pt = f.passes;
  std::printf("bench view: %s at %dx%d (%s)\n", f.input.c_str(), f.width, f.height, gl.c_str());
  std::printf("  load + FA + sweeper + first surface: %.0f ms, %zu triangles\n", f.loadMs, f.triangles);
  std::printf("  %-8s %6s %9s %9s %9s %7s\n", "phase", "frames", "mean ms", "median", "p95", "fps");
  std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (%llu surfaces shown, %.2f/s)\n", "sweep", sw.frames,
              sw.mean, sw.median, sw.p95, sw.fps, f.meshesShown, f.meshesShown / f.sweepSeconds);
  std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (interactive frames at adaptive size)\n", "rotate",
              ro.frames, ro.mean, ro.median, ro.p95, ro.fps);
  std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (interactive frames at full size)\n", "rotate", rf.frames,
              rf.mean, rf.median, rf.p95, rf.fps);
  std::printf("  one full-size interactive frame, GPU ms: projection %.1f, silhouette %.1f, advection %.1f, "
              "composite %.1f\n",
              pt.projection, pt.silhouette, pt.advection, pt.composite);
  std::printf("  still: converged in %d frames, %.0f ms\n", f.stillFrames, f.stillMs);
  if (!f.rotateTractsMs.empty()) {
    std::printf("  tracts: %zu points, %zu within 3 mm of the surface; loaded and selected in %.0f ms\n",
                f.tractPoints, f.tractsShown, f.tractsReadyMs);
    std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (rotating with the tracts drawn)\n", "+tracts", rt.frames,
                rt.mean, rt.median, rt.p95, rt.fps);
    std::printf("  still with tracts: converged in %d frames, %.0f ms\n", f.tractsStillFrames, f.tractsStillMs);
  }
  std::printf("  load average %.2f on %u cores while measuring\n", loadAverage(), std::thread::hardware_concurrency());
  std::printf("  goal: >= 15 fps while sweeping and rotating: %s\n",
              sw.fps >= 15 && ro.fps >= 15 ? "met" : "NOT met");
}

} // namespace

int benchView(const CommandArgs& argv) {
  ParsedOptions args(benchViewOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  ViewFigures f;
  const bool json = args.flag("json"), tractsOn = !args.flag("no-tracts");
  const auto dataDir = args.get("data");
  f.input = args.text("input");
  std::string tractsPath = args.text("tracts");
  parseSize(args.text("size"), f.width, f.height);
  const int frames = args.integer("frames");
  args.finish();
  if (f.input.empty()) {
    auto dir = findSharedDataDir(dataDir);
    if (!dir) throw InputError("bench view: shared data not found (give --data DIR or --input TENSOR)");
    f.input = (*dir / "iu_prisma_dwi" / "derived" / "dti_tensor.nii.gz").string();
    if (tractsPath.empty()) tractsPath = (*dir / "iu_prisma_dwi" / "derived" / "tracks_det.tck").string();
  }

  render::GlContext& gl = render::GlContext::headless();
  ViewBench bench(f.width, f.height, frames);
  f.loadMs = bench.load(f.input);
  bench.converge(300); // warm-up
  bench.sweep(f);
  // Rotating: interactive frames at the scene's interactive scale, then at full size.
  f.rotateMs = bench.rotate();
  bench.scene().setInteractiveScale(1.0);
  f.rotateFullMs = bench.rotate();
  bench.scene().setInteractiveScale(0.5);
  bench.still(500, f.stillFrames, f.stillMs);
  f.passes = bench.passTimes();
  f.triangles = bench.scene().state().triangles;
  if (!tractsPath.empty() && tractsOn) bench.tracts(tractsPath, f);
  gl.checkErrors("bench view");

  if (json)
    printViewJson(f, gl.description());
  else
    printViewTable(f, gl.description());
  return 0;
}

} // namespace dtf::app
