// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench overlay`: the tract overlay (render/tract_renderer.h, render/tract_layer.h) over a finished
// fabric, and the near-surface selection (surfaces/analyses/near_surface.h).
//   draw:      ms of one full draw (every display point): the real brain's axial slice 22 with 2000 tracts of
//              the shared deterministic tractogram (all, and the default 3 mm slab), and a synthetic
//              tractogram of 1M points over a plane. GPU time from GL_TIME_ELAPSED, wall time with glFinish.
//   budgeted:  the viewer's path: the TractLayer under a TractBudget, per frame while the camera rotates
//              (moving) and after it stops (still: chunks of the full set until complete), wall ms of the
//              tract work per frame (fabric frames not counted).
//   selection: near-surface selection (3 mm) of the brain's tracts against its FA 0.25 isosurface and of the
//              1M-point tractogram against a sphere of 36k triangles: one exact query per point on one thread
//              (the former method) against the bounded, prefiltered, threaded selection.
#include "app/bench/bench.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "render/reference/scenes.h"
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "surfaces/analyses/near_surface.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

namespace dtf::app {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct DrawResult {
  std::string name;
  std::size_t points = 0, lines = 0;
  double gpuMs = 0, wallMs = 0;
};

struct Scene {
  const Mesh* mesh;
  const TensorField* field;
  const Polylines* tracts;
  render::TractStyle style;
  render::StandardView view;
};

render::Camera setUp(render::FabricRenderer& fabric, const Scene& s, int width, int height) {
  fabric.setMesh(*s.mesh);
  fabric.setField(*s.field);
  fabric.resize(width, height);
  glm::vec3 lo, hi;
  s.mesh->bounds(lo, hi);
  return render::Camera::standard(s.view, lo, hi, double(width) / height);
}

DrawResult timeDraw(const std::string& name, render::FabricRenderer& fabric, const Scene& s,
                    render::TractRenderer& tr, int width, int height, int frames) {
  const render::Camera cam = setUp(fabric, s, width, height);
  render::FabricParams p;
  p.stillMaxIterations = 20;
  fabric.renderStill(cam, p);
  render::Query q = render::createQuery(GL_TIME_ELAPSED);
  glBindFramebuffer(GL_FRAMEBUFFER, fabric.output().id());
  tr.draw(fabric.frameView(), s.style); // warm-up
  glFinish();
  DrawResult r{name, tr.pointCount(), tr.lineCount(), 0, 0};
  const auto t0 = Clock::now();
  for (int f = 0; f < frames; ++f) {
    glBeginQuery(GL_TIME_ELAPSED, q.id());
    tr.draw(fabric.frameView(), s.style);
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
    r.gpuMs += double(ns) * 1e-6;
  }
  glFinish();
  r.wallMs = msSince(t0) / frames;
  r.gpuMs /= frames;
  render::checkGl("bench overlay " + name);
  return r;
}

struct BudgetResult {
  std::string name;
  double movingMs = 0, movingMaxMs = 0, movingSegments = 0, movingLevel = 0;
  int stillFrames = 0;
  double stillMs = 0, stillMaxMs = 0, stillTotalMs = 0;
  std::size_t chunk = 0, fullSegments = 0;
};

// The viewer's tract path: a layer under a budget, `frames` frames of a rotating camera, then still frames
// until the full set is on screen.
BudgetResult timeBudgeted(const std::string& name, render::FabricRenderer& fabric, const Scene& s,
                          render::TractRenderer& tr, int width, int height, int frames) {
  render::Camera cam = setUp(fabric, s, width, height);
  render::FabricParams p;
  render::TractLayer layer;
  render::TractBudget budget;
  BudgetResult r{name};
  r.fullSegments = tr.segmentCount(0);
  auto tractFrame = [&](bool fabricChanged, bool moving) {
    int level = 0;
    std::size_t seg = 0;
    double ms = 0;
    while (layer.takeTiming(level, seg, ms))
      budget.measured(level, seg, ms);
    render::TractLayer::Frame f;
    f.fabric = &fabric.output();
    f.fabricChanged = fabricChanged;
    f.view = fabric.frameView();
    f.style = s.style;
    f.moving = moving;
    f.draw = budget.choose(tr);
    f.chunk = budget.chunk();
    const auto t0 = Clock::now();
    layer.frame(tr, f);
    glFinish();
    return msSince(t0);
  };
  for (int i = 0; i < frames; ++i) {
    cam.trackball({0, 0}, {0.02, 0.01});
    fabric.renderFrame(cam, p);
    glFinish();
    const double ms = tractFrame(true, true);
    if (i < 3) continue; // the budget settles from its initial guess
    r.movingMs += ms;
    r.movingMaxMs = std::max(r.movingMaxMs, ms);
    r.movingSegments += double(layer.shownSegments());
    r.movingLevel += layer.shownLevel();
  }
  const int counted = std::max(frames - 3, 1);
  r.movingMs /= counted;
  r.movingSegments /= counted;
  r.movingLevel /= counted;
  r.chunk = budget.chunk();
  while (!layer.complete() && r.stillFrames < 1000) {
    const double ms = tractFrame(false, false);
    r.stillTotalMs += ms;
    r.stillMaxMs = std::max(r.stillMaxMs, ms);
    ++r.stillFrames;
  }
  r.stillMs = r.stillTotalMs / std::max(r.stillFrames, 1);
  render::checkGl("bench overlay " + name);
  return r;
}

struct SelectResult {
  std::string name;
  std::size_t points = 0, triangles = 0, kept = 0;
  double treeMs = 0, exhaustiveMs = -1, fastOneThreadMs = 0, fastMs = 0;
  int threads = 1;
};

SelectResult timeSelection(const std::string& name, const Polylines& tracts, const Mesh& mesh,
                           bool reference) {
  SelectResult r{name, tracts.points.size(), mesh.triangleCount()};
  const auto tree0 = Clock::now();
  const surfaces::DistanceQuery query(mesh);
  r.treeMs = msSince(tree0);
  surfaces::NearSurfaceOptions o;
  if (reference) {
    o.exhaustive = true;
    o.threads = 1;
    auto t0 = Clock::now();
    r.kept = surfaces::selectNearSurface(tracts, query, 3.0, o).points.size();
    r.exhaustiveMs = msSince(t0);
  }
  o.exhaustive = false;
  o.threads = 1;
  auto t0 = Clock::now();
  const std::size_t kept = surfaces::selectNearSurface(tracts, query, 3.0, o).points.size();
  r.fastOneThreadMs = msSince(t0);
  if (reference && kept != r.kept)
    std::fprintf(stderr, "warning: %s: the fast selection kept %zu points, the exhaustive one %zu\n",
                 name.c_str(), kept, r.kept);
  r.kept = kept;
  o.threads = 0;
  r.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  t0 = Clock::now();
  surfaces::selectNearSurface(tracts, query, 3.0, o);
  r.fastMs = msSince(t0);
  return r;
}

// nLines helices of nPoints each filling a 100 mm box (world mm).
Polylines syntheticTracts(std::size_t nLines, std::size_t nPoints) {
  Polylines l;
  l.points.reserve(nLines * nPoints);
  l.offsets.reserve(nLines + 1);
  l.offsets.push_back(0);
  for (std::size_t i = 0; i < nLines; ++i) {
    const float cx = float(i % 100) - 50.0f, cy = float(i / 100 % 100) - 50.0f, ph = 0.37f * float(i);
    for (std::size_t k = 0; k < nPoints; ++k) {
      const float t = float(k) / float(nPoints - 1);
      l.points.emplace_back(cx + 4.0f * std::cos(ph + 12.0f * t), cy + 4.0f * std::sin(ph + 12.0f * t),
                            -50.0f + 100.0f * t);
    }
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  return l;
}

} // namespace

const OptionTable& benchOverlayOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench overlay";
    t.intro =
        "The tract overlay over a finished fabric: one full draw (brain slice 22 + 2000 tracts, a synthetic\n"
        "1M-point tractogram), the viewer's budgeted layer while moving and until the still image is\n"
        "complete, and the 3 mm near-surface selection (brain tracts vs FA 0.25, 1M points vs a 36k-triangle\n"
        "sphere).";
    t.options = {
        O::text("size", "WxH", "image size", "1024x768").checkedBy(checkSize),
        O::integer("frames", "N", 10, closedRange(1, 1000), "timed frames per case"),
        sharedDataOption(),
        O::flag("no-reference", "skip the slow exhaustive selection the near-surface selection is compared with"),
    };
    return t;
  }();
  return table;
}

int benchOverlay(const CommandArgs& argv) {
  ParsedOptions args(benchOverlayOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  int width = 1024, height = 768;
  parseSize(args.text("size"), width, height);
  const int frames = args.integer("frames");
  const auto dataDir = args.get("data");
  const bool reference = !args.flag("no-reference");
  args.finish();

  auto& ctx = render::GlContext::headless();
  render::FabricRenderer fabric;
  render::TractRenderer tr;
  std::vector<DrawResult> draws;
  std::vector<BudgetResult> budgeted;
  std::vector<SelectResult> selections;
  const Mesh plane = render::reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 110, 110, 16);
  const TensorField planeField =
      render::reference::constantField(render::reference::centredGrid(48, 2.5), {0, 1, 0});
  const Polylines synthetic = syntheticTracts(5000, 200);
  if (auto dir = findSharedDataDir(dataDir)) {
    const auto tensor = *dir / "iu_prisma_dwi/derived/dti_tensor.nii.gz";
    const auto tck = *dir / "iu_prisma_dwi/derived/tracks_det.tck";
    if (std::filesystem::exists(tensor) && std::filesystem::exists(tck)) {
      const TensorField field = io::readTensorVolume(tensor.string()).field;
      const ScalarVolume fa = computeFaMap(field);
      const Mesh slice = session::buildSurface(session::parseSurfaceSpec("slice=axial:22"), field, fa);
      const Polylines all = session::readTracts(tck.string());
      Scene scene{&slice, &field, &all, {}, render::StandardView::Axial};
      tr.setTracts(all);
      draws.push_back(timeDraw("brain_slice22_2000_all", fabric, scene, tr, width, height, frames));
      scene.style.plane = surfaces::meshPlane(slice).value_or(glm::vec4(0, 0, 1, -slice.positions.front().z));
      scene.style.slabMm = 3.0f;
      draws.push_back(timeDraw("brain_slice22_2000_slab3", fabric, scene, tr, width, height, frames));
      selections.push_back(
          timeSelection("brain_2000_vs_fa025", all,
                        session::buildSurface(session::parseSurfaceSpec("fa=0.25"), field, fa), reference));
    }
  }
  Scene scene{&plane, &planeField, &synthetic, {}, render::StandardView::Superior};
  tr.setTracts(synthetic);
  draws.push_back(timeDraw("synthetic_1M", fabric, scene, tr, width, height, frames));
  budgeted.push_back(
      timeBudgeted("synthetic_1M", fabric, scene, tr, width, height, std::max(frames, 10) + 3));
  selections.push_back(timeSelection("synthetic_1M_vs_sphere", synthetic,
                                     render::reference::uvSphere({0, 0, 0}, 40, 96, 192), reference));

  std::printf("dtfabric bench overlay: %dx%d, %d frames, %s\n", width, height, frames,
              ctx.description().c_str());
  std::printf("full draw (every display point)\n");
  std::printf("  %-26s %9s %7s | %9s %9s\n", "case", "points", "lines", "GPU ms", "wall ms");
  for (const auto& r : draws)
    std::printf("  %-26s %9zu %7zu | %9.2f %9.2f\n", r.name.c_str(), r.points, r.lines, r.gpuMs, r.wallMs);
  std::printf(
      "budgeted layer (target %.0f ms of tract drawing per frame; wall ms of all tract work per frame)\n",
      render::TractBudget().targetMs());
  for (const auto& r : budgeted) {
    std::printf("  %-26s moving: %.1f ms/frame (max %.1f), %.0f segments drawn (mean level %.1f; level 0 has "
                "%zu)\n",
                r.name.c_str(), r.movingMs, r.movingMaxMs, r.movingSegments, r.movingLevel, r.fullSegments);
    std::printf("  %-26s still:  full set after %d frames of %zu segments, %.1f ms/frame (max %.1f), %.0f ms "
                "in all\n",
                "", r.stillFrames, r.chunk, r.stillMs, r.stillMaxMs, r.stillTotalMs);
  }
  std::printf("near-surface selection (3 mm)\n");
  std::printf("  %-26s %9s %9s %9s | %9s %13s %13s %13s\n", "case", "points", "triangles", "kept", "tree ms",
              "exhaustive ms", "fast 1 thr ms", "fast ms");
  for (const auto& r : selections) {
    char ex[32] = "-";
    if (r.exhaustiveMs >= 0) std::snprintf(ex, sizeof ex, "%.1f", r.exhaustiveMs);
    std::printf("  %-26s %9zu %9zu %9zu | %9.1f %13s %13.1f %10.1f (%d thr)\n", r.name.c_str(), r.points,
                r.triangles, r.kept, r.treeMs, ex, r.fastOneThreadMs, r.fastMs, r.threads);
  }
  return 0;
}

} // namespace dtf::app
