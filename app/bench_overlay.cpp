// `dtfabric bench overlay`: ms/frame of the tract overlay pass alone (render/tract_renderer.h) drawn over a
// finished fabric: the real brain's axial slice 22 with 2000 tracts of the shared deterministic tractogram
// (all shown, and the default 3 mm slab), and a synthetic tractogram of 1M points over a plane. GPU time
// from GL_TIME_ELAPSED, wall time with glFinish.
#include "app/args.h"
#include "app/bench.h"
#include "app/render_split.h"
#include "app/surface_spec.h"
#include "app/tract_files.h"

#include "io/model/error.h"
#include "io/tensor_io.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "render/reference/scenes.h"
#include "render/tract_renderer.h"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace dtf::app {

namespace {

struct OverlayResult {
  std::string name;
  std::size_t points = 0, lines = 0;
  double gpuMs = 0, wallMs = 0;
};

OverlayResult timeOverlay(const std::string& name, render::FabricRenderer& fabric, const Mesh& mesh,
                          const TensorField& field, const Polylines& tracts, const render::TractStyle& style,
                          render::StandardView view, int width, int height, int frames) {
  fabric.setMesh(mesh);
  fabric.setField(field);
  fabric.resize(width, height);
  glm::vec3 lo, hi;
  mesh.bounds(lo, hi);
  const render::Camera cam = render::Camera::standard(view, lo, hi, double(width) / height);
  render::FabricParams p;
  p.stillMaxIterations = 20;
  fabric.renderStill(cam, p);
  render::TractRenderer tr;
  tr.setTracts(tracts);
  render::Query q = render::createQuery(GL_TIME_ELAPSED);
  glBindFramebuffer(GL_FRAMEBUFFER, fabric.output().id());
  tr.draw(fabric.frameView(), style); // warm-up
  glFinish();
  OverlayResult r{name, tr.pointCount(), tr.lineCount(), 0, 0};
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    glBeginQuery(GL_TIME_ELAPSED, q.id());
    tr.draw(fabric.frameView(), style);
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
    r.gpuMs += double(ns) * 1e-6;
  }
  glFinish();
  const auto t1 = std::chrono::steady_clock::now();
  r.wallMs = std::chrono::duration<double, std::milli>(t1 - t0).count() / frames;
  r.gpuMs /= frames;
  render::checkGl("bench overlay " + name);
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

int benchOverlay(const CommandArgs& argv) {
  Args args(argv, {"help"});
  if (args.flag("help")) {
    std::printf("usage: dtfabric bench overlay [--size 1024x768] [--frames N] [--data DIR]\n"
                "  ms/frame of the tract overlay pass over a finished fabric: brain axial slice 22 with\n"
                "  2000 tracts (all / 3 mm slab), and a synthetic 1M-point tractogram over a plane\n");
    return 0;
  }
  int width = 1024, height = 768;
  if (auto s = args.get("size")) parseSize(*s, width, height);
  const int frames = args.getInt("frames", 10);
  if (frames < 1 || frames > 1000) throw UsageError("--frames must be in [1, 1000]");
  const auto dataDir = args.get("data");
  args.finish();

  auto& ctx = render::GlContext::headless();
  render::FabricRenderer fabric;
  std::vector<OverlayResult> results;
  if (auto dir = findSharedDataDir(dataDir)) {
    const auto tensor = *dir / "iu_prisma_dwi/derived/dti_tensor.nii.gz";
    const auto tck = *dir / "iu_prisma_dwi/derived/tracks_det.tck";
    if (std::filesystem::exists(tensor) && std::filesystem::exists(tck)) {
      TensorField field = io::readTensorVolume(tensor.string()).field;
      Mesh slice = buildSurface(parseSurfaceSpec("slice=axial:22"), field, computeFaMap(field));
      Polylines all = readTracts(tck.string());
      Polylines first;
      const std::size_t n = std::min<std::size_t>(all.lineCount(), 2000);
      first.offsets.assign(all.offsets.begin(), all.offsets.begin() + static_cast<std::ptrdiff_t>(n) + 1);
      first.points.assign(all.points.begin(), all.points.begin() + first.offsets.back());
      render::TractStyle style;
      results.push_back(timeOverlay("brain_slice22_2000_all", fabric, slice, field, first, style,
                                    render::StandardView::Axial, width, height, frames));
      style.plane = meshPlane(slice).value_or(glm::vec4(0, 0, 1, -slice.positions.front().z));
      style.slabMm = 3.0f;
      results.push_back(timeOverlay("brain_slice22_2000_slab3", fabric, slice, field, first, style,
                                    render::StandardView::Axial, width, height, frames));
    }
  }
  const Mesh plane = render::reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 110, 110, 16);
  const Grid grid = render::reference::centredGrid(48, 2.5);
  const TensorField field = render::reference::constantField(grid, {0, 1, 0});
  results.push_back(timeOverlay("synthetic_1M", fabric, plane, field, syntheticTracts(5000, 200), {},
                                render::StandardView::Superior, width, height, frames));
  std::printf("dtfabric bench overlay: %dx%d, %d frames, %s\n", width, height, frames,
              ctx.description().c_str());
  std::printf("%-26s %9s %7s | %9s %9s\n", "case", "points", "lines", "GPU ms", "wall ms");
  for (const auto& r : results)
    std::printf("%-26s %9zu %7zu | %9.2f %9.2f\n", r.name.c_str(), r.points, r.lines, r.gpuMs, r.wallMs);
  return 0;
}

} // namespace dtf::app
