// `dtfabric bench view`: frame times of the viewer's scene (app/viewer/viewer.h, the code the window runs) while
// the FA threshold is swept and while the camera rotates, on the real brain's FA isosurface. Runs in the
// headless context: the window adds only ImGui and a blit.
#include "app/bench/bench.h"
#include "app/cli/options.h"
#include "app/cli/args.h"
#include "app/viewer/viewer.h"
#include "io/model/error.h"
#include "render/gl_context.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <epoxy/gl.h>
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

int benchView(const CommandArgs& argv) {
  ParsedOptions args(benchViewOptions(), argv);
  if (args.helpRequested()) {
    std::fputs(benchViewOptions().help().c_str(), stdout);
    return 0;
  }
  const bool json = args.flag("json"), tractsOn = !args.flag("no-tracts");
  const auto dataDir = args.get("data");
  std::string input = args.text("input");
  std::string tractsPath = args.text("tracts");
  int width = 1024, height = 768;
  parseSize(args.text("size"), width, height);
  const int frames = args.integer("frames");
  args.finish();
  if (input.empty()) {
    auto dir = findSharedDataDir(dataDir);
    if (!dir) throw InputError("bench view: shared data not found (give --data DIR or --input TENSOR)");
    input = (*dir / "iu_prisma_dwi" / "derived" / "dti_tensor.nii.gz").string();
    if (tractsPath.empty()) tractsPath = (*dir / "iu_prisma_dwi" / "derived" / "tracks_det.tck").string();
  }

  render::GlContext& gl = render::GlContext::headless();
  ViewerScene scene("fa=0.25");
  const auto loadStart = Clock::now();
  scene.apply(ui::LoadFile{input, "auto"});
  waitSettled(scene, 300);
  const double loadMs = std::chrono::duration<double, std::milli>(Clock::now() - loadStart).count();

  // One pass of the window loop without ImGui: take worker results, render what changed. Like the window
  // under vsync, a loop iteration takes at least kVsyncMs.
  constexpr double kVsyncMs = 1000.0 / 60.0;
  auto frame = [&] {
    const auto t0 = Clock::now();
    scene.update();
    scene.render(width, height);
    glFinish();
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (ms < kVsyncMs) {
      std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(kVsyncMs - ms));
      ms = kVsyncMs;
    }
    scene.setFrameMs(ms);
    return ms;
  };
  // Warm-up: converge once.
  for (int i = 0; i < 300 && !scene.converged(); ++i)
    frame();

  // Sweep: the slider moves every frame, as when dragged, for `frames` frames; extraction runs on the worker
  // meanwhile and each new surface restarts the fabric (interactive, then still refinement).
  std::vector<double> sweepMs;
  const auto meshesBefore = scene.meshSerial();
  const auto sweepStart = Clock::now();
  for (int i = 0; i < frames; ++i) {
    const double phase = static_cast<double>(i % 120) / 120.0;
    const double t = 0.15 + 0.30 * (phase < 0.5 ? 2 * phase : 2 - 2 * phase);
    scene.apply(ui::SetFaThreshold{t});
    sweepMs.push_back(frame());
  }
  const double sweepSeconds = std::chrono::duration<double>(Clock::now() - sweepStart).count();
  const auto meshesShown = scene.meshSerial() - meshesBefore;
  waitSettled(scene, 120);

  // Rotate: a drag every frame, interactive frames at the scene's interactive scale, then at full size.
  auto rotate = [&] {
    std::vector<double> ms;
    for (int i = 0; i < frames; ++i) {
      scene.apply(ui::Rotate{6.0, 2.0});
      ms.push_back(frame());
    }
    return ms;
  };
  std::vector<double> rotateMs = rotate();
  scene.setInteractiveScale(1.0);
  std::vector<double> rotateFullMs = rotate();
  scene.setInteractiveScale(0.5);
  // Still: frames until the fabric converges after the camera stops.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  int stillFrames = 0;
  double stillMs = 0;
  while (!scene.converged() && stillFrames < 500) {
    stillMs += frame();
    ++stillFrames;
  }
  // GPU pass times of one full-size interactive frame.
  render::FabricRenderer& full = scene.paneRenderer(0);
  full.setTiming(true);
  scene.setInteractiveScale(1.0);
  scene.redraw();
  frame();
  const render::PassTimes pt = full.lastTimes();
  full.setTiming(false);
  const std::size_t triangles = scene.state().triangles;
  // Tracts: the time to select those within 3 mm of the FA isosurface (worker), then rotating with them
  // drawn through the budgeted tract layer, interactive frames at the adaptive size.
  std::vector<double> rotateTractsMs;
  double tractsReadyMs = 0, tractsStillMs = 0;
  int tractsStillFrames = 0;
  std::size_t tractPoints = 0, tractsShown = 0;
  if (!tractsPath.empty() && tractsOn) {
    scene.setInteractiveScale(0.5); // as in the first rotation
    const auto t0 = Clock::now();
    scene.apply(ui::LoadTracts{tractsPath});
    waitSettled(scene, 300);
    tractsReadyMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    tractPoints = scene.state().tractPoints;
    tractsShown = scene.state().tractsShownPoints;
    for (int i = 0; i < 300 && !scene.converged(); ++i)
      frame();
    rotateTractsMs = rotate();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    while (!scene.converged() && tractsStillFrames < 1000) {
      tractsStillMs += frame();
      ++tractsStillFrames;
    }
  }
  gl.checkErrors("bench view");

  const double load = loadAverage();
  const Stats sw = stats(sweepMs), ro = stats(rotateMs), rf = stats(rotateFullMs), rt = stats(rotateTractsMs);
  if (json) {
    std::printf(
        "{\"input\": \"%s\", \"width\": %d, \"height\": %d, \"load_ms\": %.1f, \"triangles\": %zu, "
        "\"sweep\": {\"frames\": %d, \"mean_ms\": %.2f, \"median_ms\": %.2f, \"p95_ms\": %.2f, \"fps\": "
        "%.1f, "
        "\"surfaces_shown\": %llu, \"surfaces_per_s\": %.2f}, "
        "\"rotate\": {\"frames\": %d, \"mean_ms\": %.2f, \"median_ms\": %.2f, \"p95_ms\": %.2f, \"fps\": "
        "%.1f}, "
        "\"rotate_full_size\": {\"mean_ms\": %.2f, \"median_ms\": %.2f, \"p95_ms\": %.2f, \"fps\": %.1f}, "
        "\"passes_ms\": {\"projection\": %.2f, \"silhouette\": %.2f, \"advection\": %.2f, \"composite\": "
        "%.2f}, "
        "\"still\": {\"frames\": %d, \"ms\": %.1f}, "
        "\"tracts\": {\"points\": %zu, \"shown\": %zu, \"load_select_ms\": %.1f, \"rotate_mean_ms\": %.2f, "
        "\"rotate_median_ms\": %.2f, \"rotate_p95_ms\": %.2f, \"rotate_fps\": %.1f, \"still_frames\": %d, "
        "\"still_ms\": %.1f}, \"load_average\": %.2f, \"gl\": \"%s\"}\n",
        input.c_str(), width, height, loadMs, triangles, sw.frames, sw.mean, sw.median, sw.p95, sw.fps,
        static_cast<unsigned long long>(meshesShown), meshesShown / sweepSeconds, ro.frames, ro.mean,
        ro.median, ro.p95, ro.fps, rf.mean, rf.median, rf.p95, rf.fps, pt.projection, pt.silhouette,
        pt.advection, pt.composite, stillFrames, stillMs, tractPoints, tractsShown, tractsReadyMs, rt.mean,
        rt.median, rt.p95, rt.fps, tractsStillFrames, tractsStillMs, load, gl.description().c_str());
  } else {
    std::printf("bench view: %s at %dx%d (%s)\n", input.c_str(), width, height, gl.description().c_str());
    std::printf("  load + FA + sweeper + first surface: %.0f ms, %zu triangles\n", loadMs, triangles);
    std::printf("  %-8s %6s %9s %9s %9s %7s\n", "phase", "frames", "mean ms", "median", "p95", "fps");
    std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (%llu surfaces shown, %.2f/s)\n", "sweep", sw.frames,
                sw.mean, sw.median, sw.p95, sw.fps, static_cast<unsigned long long>(meshesShown),
                meshesShown / sweepSeconds);
    std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (interactive frames at adaptive size)\n", "rotate",
                ro.frames, ro.mean, ro.median, ro.p95, ro.fps);
    std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (interactive frames at full size)\n", "rotate",
                rf.frames, rf.mean, rf.median, rf.p95, rf.fps);
    std::printf(
        "  one full-size interactive frame, GPU ms: projection %.1f, silhouette %.1f, advection %.1f, "
        "composite %.1f\n",
        pt.projection, pt.silhouette, pt.advection, pt.composite);
    std::printf("  still: converged in %d frames, %.0f ms\n", stillFrames, stillMs);
    if (!rotateTractsMs.empty()) {
      std::printf("  tracts: %zu points, %zu within 3 mm of the surface; loaded and selected in %.0f ms\n",
                  tractPoints, tractsShown, tractsReadyMs);
      std::printf("  %-8s %6d %9.2f %9.2f %9.2f %7.1f   (rotating with the tracts drawn)\n", "+tracts",
                  rt.frames, rt.mean, rt.median, rt.p95, rt.fps);
      std::printf("  still with tracts: converged in %d frames, %.0f ms\n", tractsStillFrames, tractsStillMs);
    }
    std::printf("  load average %.2f on %u cores while measuring\n", load,
                std::thread::hardware_concurrency());
    std::printf("  goal: >= 15 fps while sweeping and rotating: %s\n",
                sw.fps >= 15 && ro.fps >= 15 ? "met" : "NOT met");
  }
  return 0;
}

} // namespace dtf::app
