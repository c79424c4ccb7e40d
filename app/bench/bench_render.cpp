// `dtfabric bench render`: GPU time per fabric pass and ms/frame of the fabric against plain Phong of the
// same mesh and camera, in the paper's Table 1 setting (1024x768, about 3/4 of the pixels covered, one
// frame = projection + silhouette + 3 advection iterations + composite), on UV spheres of about 41k and
// 572k triangles with an anisotropic Hessian field, and on the real brain's FA 0.25 isosurface when the
// shared data is there.
#include "app/bench/bench.h"
#include "app/cli/args.h"
#include "app/scene/surface_spec.h"
#include "io/model/error.h"
#include "io/tensor_io.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "render/reference/scenes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace dtf::app {

namespace {

namespace fs = std::filesystem;

struct Case {
  std::string name;
  Mesh mesh;
  TensorField field;
  std::optional<FibreSet> fibres; // set: the multi-population fabric (ColourMode::Fibres) of these fibres
};

struct Result {
  std::string name;
  std::size_t triangles = 0;
  double coverage = 0;
  double fabricMs = 0, movingMs = 0, movingHalfMs = 0, phongMs = 0;
  double fabricCpuMs = 0, phongCpuMs = 0; // process CPU time (all llvmpipe threads) per frame
  render::PassTimes passes;
  int frames = 0;
};

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Anisotropic sphere field (Hessian of |x|^2 + c xyz) on a grid just enclosing a sphere of radius r.
Case sphereCase(const std::string& name, int rings, int segments) {
  const double r = 50.0;
  Case c;
  c.name = name;
  c.mesh = render::reference::uvSphere({0, 0, 0}, r, rings, segments);
  Grid g = render::reference::centredGrid(48, 2.0 * r * 1.1 / 47.0);
  c.field = render::reference::hessianField(g, [r](const glm::dvec3& p) { return render::reference::sphereFunction(p, r); }, 0.5);
  return c;
}

// The 41k sphere with three fibre populations per voxel: the field's eigenvectors with amplitudes 1, 0.7
// and 0.5 (two roughly in the surface, one across it), for the three-field fabric against the tensor's two.
Case fibreSphereCase(const Case& sphere) {
  Case c;
  c.name = sphere.name + "_fibres3";
  c.mesh = sphere.mesh;
  c.field = sphere.field;
  FibreSet f = makeFibreSet(sphere.field.grid, 3);
  const float amplitude[3] = {1.0f, 0.7f, 0.5f};
  for (std::size_t v = 0; v < sphere.field.tensors.size(); ++v) {
    if (!sphere.field.valid[v]) continue;
    const EigenSystem e = eigenDecompose(sphere.field.tensors[v].toMat());
    for (int k = 0; k < 3; ++k) f.fibres[v * 3 + static_cast<std::size_t>(k)] = {glm::vec3(e.vectors[k]), amplitude[k]};
  }
  c.fibres = std::move(f);
  return c;
}

std::optional<Case> brainCase(const std::optional<std::string>& dataDir) {
  auto dir = findSharedDataDir(dataDir);
  if (!dir) return std::nullopt;
  fs::path path = *dir / "iu_prisma_dwi/derived/dti_tensor.nii.gz";
  if (!fs::exists(path)) return std::nullopt;
  Case c;
  c.name = "brain_fa025";
  c.field = io::readTensorVolume(path.string()).field;
  ScalarVolume fa = computeFaMap(c.field);
  c.mesh = buildSurface(parseSurfaceSpec("fa=0.25"), c.field, fa);
  return c;
}

Result runCase(render::FabricRenderer& r, const Case& c, int width, int height, int frames, render::ColourMode mode) {
  Result res;
  res.name = c.name;
  res.triangles = c.mesh.triangleCount();
  res.frames = frames;
  r.setMesh(c.mesh);
  r.setField(c.field);
  if (c.fibres) r.setFibres(*c.fibres);
  r.resize(width, height);
  glm::vec3 lo, hi;
  c.mesh.bounds(lo, hi);
  render::Camera cam = render::Camera::standard(render::StandardView::Superior, lo, hi, double(width) / height);
  render::FabricParams p;
  p.iterations = 3;
  p.colour = c.fibres ? render::ColourMode::Fibres : mode;
  // Zoom until about 3/4 of the viewport is covered (paper Table 1), measured on the composited image.
  auto coverage = [&] {
    Image img = r.readback();
    std::size_t lit = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4) lit += (img.rgba[i] | img.rgba[i + 1] | img.rgba[i + 2]) != 0;
    return double(lit) / (double(width) * height);
  };
  for (int i = 0; i < 5; ++i) {
    r.renderFrame(cam, p);
    res.coverage = coverage();
    if (std::abs(res.coverage - 0.75) < 0.03 || res.coverage <= 0) break;
    cam.zoom(std::clamp(std::sqrt(res.coverage / 0.75), 0.5, 2.0));
  }
  // Static camera: the paper's frame (projection, silhouette, 3 advections, composite), state carried on.
  r.setTiming(true);
  render::PassTimes sum;
  std::clock_t c0 = std::clock();
  auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    r.renderFrame(cam, p);
    render::PassTimes t = r.lastTimes(); // waits for the frame
    sum.projection += t.projection;
    sum.silhouette += t.silhouette;
    sum.advection += t.advection;
    sum.composite += t.composite;
  }
  glFinish();
  res.fabricMs = msSince(t0) / frames;
  res.fabricCpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / frames;
  res.passes = {sum.projection / frames, sum.silhouette / frames, sum.advection / frames, sum.composite / frames, 0};
  // Moving camera: a small trackball step every frame; the advection restarts from beta each frame.
  t0 = std::chrono::steady_clock::now();
  render::Camera moving = cam;
  for (int f = 0; f < frames; ++f) {
    moving.trackball({0.0, 0.0}, {0.01, 0.0});
    r.renderFrame(moving, p);
    glFinish();
  }
  res.movingMs = msSince(t0) / frames;
  // The same at half internal resolution while moving (FabricParams::movingScale).
  render::FabricParams half = p;
  half.movingScale = 0.5;
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    moving.trackball({0.0, 0.0}, {0.01, 0.0});
    r.renderFrame(moving, half);
    glFinish();
  }
  res.movingHalfMs = msSince(t0) / frames;
  // Plain Phong of the same mesh and camera.
  double phongGpu = 0;
  c0 = std::clock();
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    r.renderPhong(cam);
    phongGpu += r.lastTimes().phong;
  }
  glFinish();
  res.phongMs = msSince(t0) / frames;
  res.phongCpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / frames;
  res.passes.phong = phongGpu / frames;
  r.setTiming(false);
  render::checkGl("bench render " + c.name);
  return res;
}

} // namespace

int benchRender(const CommandArgs& argv) {
  Args args(argv, {"json", "help", "no-brain", "no-peer"});
  if (args.flag("help")) {
    std::printf("usage: dtfabric bench render [--size 1024x768] [--frames N] [--json] [--no-brain] [--data DIR]\n"
                "       [--color medical|engineering] [--only CASE[,CASE...]] (sphere_41k, sphere_41k_fibres3, sphere_572k, brain_fa025)\n"
                "       [--no-peer] [--peer-frames N] [--peer-png FILE]\n"
                "  fabric frames (projection + silhouette + 3 advection iterations + composite, paper Table 1)\n"
                "  against plain Phong of the same mesh and camera, about 3/4 of the pixels covered;\n"
                "  GPU times per pass from GL_TIME_ELAPSED queries, ms/frame from the wall clock.\n"
                "  Peer on sphere_41k when pvbatch is on the PATH (Debian package paraview): ParaView's\n"
                "  Surface LIC with its defaults and with 1 step, and its plain surface (--peer-frames,\n"
                "  default min(N, 10); --peer-png saves one of its LIC frames).\n");
    return 0;
  }
  const bool json = args.flag("json");
  int width = 1024, height = 768;
  if (auto s = args.get("size")) parseSize(*s, width, height);
  const int frames = args.getInt("frames", 10);
  if (frames < 1 || frames > 1000) throw UsageError("--frames must be in [1, 1000]");
  const bool noBrain = args.flag("no-brain");
  const std::string colour = args.getOr("color", "medical");
  if (colour != "medical" && colour != "engineering") throw UsageError("--color must be medical or engineering");
  const auto mode = colour == "medical" ? render::ColourMode::Medical : render::ColourMode::Engineering;
  const std::string only = args.getOr("only", "");
  const auto dataDir = args.get("data");
  const bool noPeer = args.flag("no-peer");
  const int peerFrames = args.getInt("peer-frames", std::min(frames, 10));
  if (peerFrames < 1 || peerFrames > 1000) throw UsageError("--peer-frames must be in [1, 1000]");
  const std::string peerPng = args.getOr("peer-png", "");
  args.finish();

  auto& ctx = render::GlContext::headless();
  render::FabricRenderer renderer;
  std::vector<Case> cases;
  cases.push_back(sphereCase("sphere_41k", 145, 144));   // 2 * 144 * 144 = 41472 triangles (Table 1, Fig. 8)
  cases.push_back(fibreSphereCase(cases.back()));        // three fibre populations on the same sphere
  cases.push_back(sphereCase("sphere_572k", 534, 536));  // 2 * 536 * 533 = 571376 triangles (Table 1, Fig. 7)
  if (!noBrain)
    if (auto b = brainCase(dataDir)) cases.push_back(std::move(*b));
  std::vector<Result> results;
  for (const auto& c : cases)
    if (only.empty() || ("," + only + ",").find("," + c.name + ",") != std::string::npos) results.push_back(runCase(renderer, c, width, height, frames, mode));
  // The peer, ParaView's Surface LIC, on sphere_41k after ours (app/bench/bench_render_peer.cpp).
  const Result* ours = results.empty() || results[0].name != "sphere_41k" ? nullptr : &results[0];
  RenderPeerResult peer;
  peer.note = noPeer ? "skipped (--no-peer)" : "ParaView Surface LIC runs on sphere_41k only";
  if (!noPeer && ours)
    peer = runRenderPeer(cases[0].mesh, cases[0].field, {width, height, peerFrames, peerPng});
  const RenderPeerOurs mine = ours ? RenderPeerOurs{ours->fabricMs, ours->movingMs, ours->phongMs,
                                                    ours->fabricCpuMs, ours->phongCpuMs}
                                   : RenderPeerOurs{};

  if (json) {
    std::printf("{\"renderer\": \"%s\", \"width\": %d, \"height\": %d, \"frames\": %d, \"cases\": [", ctx.description().c_str(),
                width, height, frames);
    for (std::size_t i = 0; i < results.size(); ++i) {
      const Result& r = results[i];
      std::printf("%s{\"name\": \"%s\", \"triangles\": %zu, \"fabric_ms\": %.2f, \"phong_ms\": %.2f, "
                  "\"moving_ms\": %.2f, \"moving_half_res_ms\": %.2f, \"fabric_cpu_ms\": %.2f, \"phong_cpu_ms\": %.2f, \"ratio\": %.2f, \"coverage\": %.3f, \"passes_ms\": {\"projection\": %.2f, "
                  "\"silhouette\": %.2f, \"advection\": %.2f, \"composite\": %.2f, \"phong\": %.2f}}",
                  i ? ", " : "", r.name.c_str(), r.triangles, r.fabricMs, r.phongMs, r.movingMs, r.movingHalfMs,
                  r.fabricCpuMs, r.phongCpuMs, r.fabricMs / std::max(r.phongMs, 1e-9), r.coverage,
                  r.passes.projection, r.passes.silhouette, r.passes.advection, r.passes.composite, r.passes.phong);
    }
    std::printf("]");
    printRenderPeerJson(peer, mine);
    std::printf("}\n");
    return 0;
  }
  double load = -1;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = -1;
    std::fclose(f);
  }
  std::printf("dtfabric bench render: %dx%d, %d frames per figure, %s, load average %.1f on %u cores\n", width, height,
              frames, ctx.description().c_str(), load, std::thread::hardware_concurrency());
  std::printf("frame = projection + silhouette + 3 advection iterations + composite (paper Table 1); goal fabric <= 95 ms\n\n");
  std::printf("%-12s %9s %6s | %9s %9s %9s %9s %6s | GPU ms: %8s %8s %8s %8s %8s\n", "case", "triangles", "cover",
              "fabric", "moving", "mov 1/2", "phong", "ratio", "project", "silhou", "advect3", "compos", "phong");
  for (const Result& r : results)
    std::printf("%-12s %9zu %5.0f%% | %6.1f ms %6.1f ms %6.1f ms %6.1f ms %6.2f | %16.2f %8.2f %8.2f %8.2f %8.2f\n",
                r.name.c_str(), r.triangles, 100 * r.coverage, r.fabricMs, r.movingMs, r.movingHalfMs, r.phongMs,
                r.fabricMs / std::max(r.phongMs, 1e-9),
                r.passes.projection, r.passes.silhouette, r.passes.advection, r.passes.composite, r.passes.phong);
  std::printf("\nCPU time per frame (all llvmpipe threads; less sensitive to other processes' load):\n");
  for (const Result& r : results)
    std::printf("  %-12s fabric %7.1f ms  phong %6.1f ms  -> uncontended on %u cores about %.0f ms / %.0f ms\n",
                r.name.c_str(), r.fabricCpuMs, r.phongCpuMs, std::thread::hardware_concurrency(),
                r.fabricCpuMs / std::max(1u, std::thread::hardware_concurrency()),
                r.phongCpuMs / std::max(1u, std::thread::hardware_concurrency()));
  std::printf("\nfabric/Phong ratio, paper Table 1 (GPU, 2010): 1.9 on the 41k sphere, 1.14 on the 572k sphere.\n");
  for (const Result& r : results)
    std::printf("  %-12s %.2f wall, %.2f CPU time\n", r.name.c_str(), r.fabricMs / std::max(r.phongMs, 1e-9),
                r.fabricCpuMs / std::max(r.phongCpuMs, 1e-9));
  const Result* two = nullptr;
  const Result* three = nullptr;
  for (const Result& r : results) {
    if (r.name == "sphere_41k") two = &r;
    if (r.name == "sphere_41k_fibres3") three = &r;
  }
  if (two && three)
    std::printf("\nthree fibre populations vs the two-direction tensor fabric on the 41k sphere (goal <= 1.5): "
                "%.2f wall, %.2f CPU time\n",
                three->fabricMs / std::max(two->fabricMs, 1e-9), three->fabricCpuMs / std::max(two->fabricCpuMs, 1e-9));
  std::printf("\nfabric: static camera, advection state carried between frames; moving: a trackball step per frame,\n"
              "the advection restarts from the mapped noise (no smearing); mov 1/2: the same with the fabric computed\n"
              "at half resolution while moving. Times are wall-clock ms/frame; CPU load from other processes inflates\n"
              "them (the load average is printed above).\n");
  printRenderPeerTable(peer, mine);
  return 0;
}

} // namespace dtf::app
