// SPDX-License-Identifier: GPL-3.0-or-later
// The peer of `dtfabric bench render`: ParaView's Surface LIC (vtkSurfaceLICInterface, Debian package
// paraview), the nearest tool that draws a LIC texture on a surface. It weaves one vector direction, so it
// gets the principal in-surface eigenvector of our tensor field per vertex. The mesh goes out as a legacy
// VTK file into a temporary folder beside a generated Python script; pvbatch runs the script (under
// xvfb-run when there is no DISPLAY: Debian's ParaView renders only through X) under timeout(1), and the
// script prints "DTF_PEER key value" lines that are parsed here. ParaView recomputes the LIC on every
// render (a static camera costs the same as a moving one on llvmpipe); the camera still turns 0.5 deg per
// frame, as a user's would. The peer never fails the bench: every failure becomes a note.
#include "app/bench/bench.h"
#include "io/formats/process.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace dtf::app {

namespace {

namespace fs = std::filesystem;

// Body of the generated script; renderPeerScript() puts the settings in front of it. The view mirrors
// bench render's: orthographic, looking down -z with +y up (the superior view), black background, zoomed
// until about 3/4 of the pixels are covered, measured on the plain surface's image.
constexpr const char* kScriptBody = R"PY(
import sys, time

def out(key, value):
    print('DTF_PEER %s %s' % (key, value), flush=True)

try:
    from paraview.simple import (CreateView, GetParaViewSourceVersion, LegacyVTKReader, Render,
                                 SaveScreenshot, Show)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
except Exception as e:
    out('error', 'cannot import paraview.simple (%s): unpack python3-paraview and set '
        'DTF_PARAVIEW_PYTHONPATH to its dist-packages (see sample_data/guide/reference.md; installing it '
        'removes libvtk9-dev)'
        % str(e).replace('\n', ' '))
    sys.exit(3)

try:
    out('version', GetParaViewSourceVersion().split()[-1])
    reader = LegacyVTKReader(FileNames=[MESH])
    view = CreateView('RenderView')
    view.ViewSize = [WIDTH, HEIGHT]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0, 0, 0]
    view.CameraParallelProjection = 1
    view.CameraPosition = [0, 0, 1000]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 1, 0]
    disp = Show(reader, view)
    disp.SetRepresentationType('Surface')
    disp.ColorArrayName = ['POINTS', '']
    view.ResetCamera()
    window = view.GetRenderWindow()
    camera = view.GetActiveCamera()

    def coverage():
        Render(view)
        grab = vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
        return float((rgb[:, :3].max(axis=1) > 0).mean())

    cover = 0.0
    for i in range(6):
        cover = coverage()
        if abs(cover - 0.75) < 0.03 or cover <= 0:
            break
        camera.SetParallelScale(camera.GetParallelScale() * min(2.0, max(0.5, (cover / 0.75) ** 0.5)))
    out('coverage', '%.3f' % cover)
    out('pixels', '%dx%d' % tuple(window.GetSize()))

    # Mean wall-clock ms/frame over FRAMES renders after one warm-up, the camera turning 0.5 deg about
    # the view-up axis before each; WaitForCompletion (glFinish) makes each frame's pixels final.
    # process_time() is pvbatch's CPU time over all its threads (llvmpipe's included).
    def timeFrames(key):
        camera.Azimuth(0.5)
        Render(view)
        window.WaitForCompletion()
        total = cpu = 0.0
        for i in range(FRAMES):
            camera.Azimuth(0.5)
            t0, c0 = time.perf_counter(), time.process_time()
            Render(view)
            window.WaitForCompletion()
            total += time.perf_counter() - t0
            cpu += time.process_time() - c0
        out(key + '_ms', '%.2f' % (1000.0 * total / FRAMES))
        out(key + '_cpu_ms', '%.2f' % (1000.0 * cpu / FRAMES))

    timeFrames('surface')
    disp.SetRepresentationType('Surface LIC')
    disp.SelectInputVectors = ['POINTS', 'v']
    out('lic_default_steps', disp.NumberOfSteps)
    timeFrames('lic_default')
    if PNG:
        SaveScreenshot(PNG, view, ImageResolution=[WIDTH, HEIGHT])
        out('png', PNG)
    disp.NumberOfSteps = 1
    timeFrames('lic_one_step')
except Exception as e:
    out('error', str(e).replace('\n', ' '))
    sys.exit(4)
)PY";

// A Python string literal.
std::string pyString(const std::string& s) {
  std::string r = "'";
  for (char c : s) {
    if (c == '\\' || c == '\'') r += '\\';
    r += c;
  }
  return r + "'";
}

// The first of `names` that is an executable on the PATH, or empty.
std::string onPath(std::initializer_list<const char*> names) {
  for (const char* name : names)
    if (std::string found = io::findOnPath(name); !found.empty()) return found;
  return {};
}

// Legacy VTK polydata: positions, triangles, the mesh normals and the vector field "v".
void writePeerMesh(const Mesh& mesh, const TensorField& field, const fs::path& path) {
  std::ofstream f(path);
  f << "# vtk DataFile Version 3.0\ndtfabric bench render peer mesh\nASCII\nDATASET POLYDATA\nPOINTS "
    << mesh.positions.size() << " float\n";
  char line[128];
  for (const glm::vec3& p : mesh.positions) {
    std::snprintf(line, sizeof line, "%.6g %.6g %.6g\n", p.x, p.y, p.z);
    f << line;
  }
  f << "POLYGONS " << mesh.triangleCount() << " " << 4 * mesh.triangleCount() << "\n";
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
    f << "3 " << mesh.indices[3 * t] << " " << mesh.indices[3 * t + 1] << " " << mesh.indices[3 * t + 2]
      << "\n";
  f << "POINT_DATA " << mesh.positions.size() << "\nNORMALS Normals float\n";
  for (const glm::vec3& n : mesh.normals) {
    std::snprintf(line, sizeof line, "%.6g %.6g %.6g\n", n.x, n.y, n.z);
    f << line;
  }
  f << "VECTORS v float\n";
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3 e = principalInSurfaceDirection(field.sampleWorld(glm::dvec3(mesh.positions[i])).toMat(),
                                                     glm::dvec3(mesh.normals[i]));
    std::snprintf(line, sizeof line, "%.6g %.6g %.6g\n", e.x, e.y, e.z);
    f << line;
  }
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

std::string lastLine(const std::string& text) {
  std::string s = text;
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' '))
    s.pop_back();
  const std::size_t nl = s.rfind('\n');
  s = nl == std::string::npos ? s : s.substr(nl + 1);
  return s.size() > 200 ? s.substr(0, 200) + "..." : s;
}

std::string readAll(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

} // namespace

glm::dvec3 principalInSurfaceDirection(const glm::dmat3& t, const glm::dvec3& n) {
  // An orthonormal tangent basis (u, v); in it T' is the 2x2 block [[a, b], [b, c]], whose larger
  // eigenvalue's eigenvector is at angle atan2(2b, a - c) / 2 from u.
  const glm::dvec3 axis = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(n, axis)), v = glm::cross(n, u);
  const double a = glm::dot(u, t * u), b = glm::dot(u, t * v), c = glm::dot(v, t * v);
  const double theta = 0.5 * std::atan2(2 * b, a - c);
  return std::cos(theta) * u + std::sin(theta) * v;
}

std::string renderPeerScript(const std::string& meshPath, const RenderPeerOptions& o) {
  std::ostringstream s;
  s << "# Generated by dtfabric bench render (app/bench/bench_render_peer.cpp): times ParaView's Surface LIC.\n"
    << "MESH = " << pyString(meshPath) << "\nWIDTH, HEIGHT = " << o.width << ", " << o.height
    << "\nFRAMES = " << std::max(1, o.frames) << "\nPNG = " << pyString(o.pngPath) << "\n"
    << kScriptBody;
  return s.str();
}

RenderPeerResult parseRenderPeerOutput(const std::string& text) {
  std::map<std::string, std::string> v;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("DTF_PEER ", 0) != 0) continue;
    const std::size_t sp = line.find(' ', 9);
    if (sp != std::string::npos) v[line.substr(9, sp - 9)] = line.substr(sp + 1);
  }
  auto number = [&](const char* key) {
    auto it = v.find(key);
    if (it == v.end()) return -1.0;
    char* end = nullptr;
    const double x = std::strtod(it->second.c_str(), &end);
    return end != it->second.c_str() && std::isfinite(x) ? x : -1.0;
  };
  RenderPeerResult r;
  r.name = "ParaView" + (v.count("version") ? " " + v["version"] : std::string()) + " Surface LIC";
  r.surfaceMs = number("surface_ms");
  r.licDefaultMs = number("lic_default_ms");
  r.licOneStepMs = number("lic_one_step_ms");
  r.surfaceCpuMs = number("surface_cpu_ms");
  r.licDefaultCpuMs = number("lic_default_cpu_ms");
  r.licOneStepCpuMs = number("lic_one_step_cpu_ms");
  r.coverage = std::max(0.0, number("coverage"));
  r.licDefaultSteps = static_cast<int>(std::max(0.0, number("lic_default_steps")));
  if (v.count("png")) r.png = v["png"];
  if (v.count("pixels")) r.pixels = v["pixels"];
  r.ran = r.surfaceMs > 0 && r.licDefaultMs > 0 && r.licOneStepMs > 0;
  if (v.count("error"))
    r.note = v["error"];
  else if (!r.ran)
    r.note = "its output lacks the timings";
  return r;
}

RenderPeerResult runRenderPeer(const Mesh& mesh, const TensorField& field, const RenderPeerOptions& o) {
  RenderPeerResult r;
  r.name = "ParaView Surface LIC";
  const std::string pv = onPath({"pvbatch", "pvpython"});
  if (pv.empty()) {
    r.note = "ParaView's pvbatch is not on the PATH (Debian package paraview); no comparison";
    return r;
  }
  const char* display = std::getenv("DISPLAY");
  const bool haveDisplay = display && *display;
  const std::string xvfb = haveDisplay ? std::string() : onPath({"xvfb-run"});
  if (!haveDisplay && xvfb.empty()) {
    r.note = pv + " is on the PATH but there is no DISPLAY and no xvfb-run to provide one; no comparison";
    return r;
  }
  std::error_code ec;
  std::string tmpl = (fs::temp_directory_path(ec) / "dtf_bench_paraview_XXXXXX").string();
  if (ec || ::mkdtemp(tmpl.data()) == nullptr) {
    r.note = "cannot create a temporary folder for the ParaView peer";
    return r;
  }
  const fs::path dir = tmpl;
  RenderPeerOptions opts = o;
  if (!opts.pngPath.empty())
    opts.pngPath = fs::absolute(opts.pngPath, ec).string(); // pvbatch's cwd may differ
  try {
    if (mesh.normals.size() == mesh.positions.size()) {
      writePeerMesh(mesh, field, dir / "mesh.vtk");
    } else {
      Mesh withNormals = mesh;
      withNormals.computeNormals();
      writePeerMesh(withNormals, field, dir / "mesh.vtk");
    }
    std::ofstream(dir / "peer.py") << renderPeerScript((dir / "mesh.vtk").string(), opts);
  } catch (const std::exception& e) {
    r.note = std::string("cannot write the peer's input: ") + e.what();
    fs::remove_all(dir, ec);
    return r;
  }
  // Generous: the default LIC took 1.9 s/frame on this machine uncontended, 9 s under load.
  const int timeoutS = 120 + 40 * (std::max(1, o.frames) + 1);
  const std::string timeout = onPath({"timeout"});
  // xvfb-run -a starts at display 99, where concurrent xvfb-runs (other test suites) race: a second
  // Xvfb on a taken number can leave the first one's clients with "bad X server connection". So take
  // a number of our own from the pid, and try another when nothing got rendered for want of a display.
  auto attempt = [&](int serverNum) {
    std::vector<std::string> argv;
    io::ProgramIo io{(dir / "out.txt").string(), (dir / "err.txt").string(), {}};
    if (const char* extra = std::getenv("DTF_PARAVIEW_PYTHONPATH"); extra && *extra) {
      const char* old = std::getenv("PYTHONPATH");
      io.environment.push_back(std::string("PYTHONPATH=") + extra + (old && *old ? ":" + std::string(old) : ""));
    }
    if (!timeout.empty()) argv.insert(argv.end(), {timeout, "-k", "10", std::to_string(timeoutS)});
    if (!xvfb.empty())
      argv.insert(argv.end(), {xvfb, "-n", std::to_string(serverNum), "-s",
                               "-screen 0 " + std::to_string(std::max(o.width, 1280)) + "x" +
                                   std::to_string(std::max(o.height, 1024)) + "x24"});
    argv.insert(argv.end(), {pv, (dir / "peer.py").string()});
    return io::runProgram(argv, io);
  };
  int code = 0;
  RenderPeerResult parsed;
  for (int i = 0; i < (xvfb.empty() ? 1 : 3); ++i) {
    code = attempt(1000 + static_cast<int>((::getpid() * 7L + i * 1009L) % 30000));
    const std::string out = readAll(dir / "out.txt"), err = readAll(dir / "err.txt");
    parsed = parseRenderPeerOutput(out);
    const bool displayFailed = err.find("Xvfb failed to start") != std::string::npos ||
                               err.find("bad X server connection") != std::string::npos;
    if (parsed.ran || out.find("DTF_PEER coverage") != std::string::npos || !displayFailed) break;
  }
  parsed.frames = std::max(1, o.frames);
  const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
  if (parsed.ran && parsed.pixels != size) { // e.g. a real display smaller than the view
    parsed.ran = false;
    parsed.note =
        "rendered at " + (parsed.pixels.empty() ? "an unknown size" : parsed.pixels) + ", not " + size;
  }
  if (parsed.ran) {
    fs::remove_all(dir, ec);
    return parsed;
  }
  // Keep the folder (mesh, script, output) for a look, unless the cause is known: no ParaView Python.
  const bool noPython = parsed.note.rfind("cannot import paraview.simple", 0) == 0;
  if (noPython) fs::remove_all(dir, ec);
  std::string why = code == 124 || code == 137 ? "timed out after " + std::to_string(timeoutS) + " s"
                                               : "exit status " + std::to_string(code);
  std::string detail = parsed.note;
  if (detail.empty() || detail == "its output lacks the timings") {
    const std::string err = lastLine(readAll(dir / "err.txt"));
    detail = err.empty() ? "no timings in its output" : err;
  }
  parsed.note = pv + " failed (" + why + "): " + detail;
  if (!noPython) parsed.note += "; script and logs kept in " + dir.string();
  return parsed;
}

void printRenderPeerTable(const RenderPeerResult& p, const RenderPeerOurs& ours) {
  if (!p.ran) {
    std::printf("\npeer: %s\n", p.note.c_str());
    return;
  }
  auto ratio = [](double a, double b) { return a > 0 && b > 0 ? a / b : 0.0; };
  std::printf("\npeer: %s (one vector direction: the principal in-surface eigenvector), sphere_41k, %.0f%% "
              "covered,\n      camera turning 0.5 deg per frame, mean of %d frames after a warm-up:\n",
              p.name.c_str(), 100 * p.coverage, p.frames);
  std::printf(
      "  LIC defaults (%d steps) %8.1f ms | LIC 1 step %7.1f ms | plain surface %6.1f ms   (wall clock)\n",
      p.licDefaultSteps, p.licDefaultMs, p.licOneStepMs, p.surfaceMs);
  if (p.licDefaultCpuMs >= 0)
    std::printf(
        "                          %8.1f ms |            %7.1f ms |               %6.1f ms   (CPU time)\n",
        p.licDefaultCpuMs, p.licOneStepCpuMs, p.surfaceCpuMs);
  if (ours.fabricMs > 0) {
    std::printf(
        "  -> its default LIC / our fabric (two directions) = %.1fx (moving camera %.1fx; goal >= 35x),\n"
        "     its 1-step LIC / our fabric = %.2fx, its plain surface / our Phong = %.2fx\n",
        ratio(p.licDefaultMs, ours.fabricMs), ratio(p.licDefaultMs, ours.movingMs),
        ratio(p.licOneStepMs, ours.fabricMs), ratio(p.surfaceMs, ours.phongMs));
    if (p.licDefaultCpuMs >= 0)
      std::printf(
          "     in CPU time: default LIC / fabric = %.1fx (moving camera %.1fx), 1-step LIC / fabric = %.2fx,\n"
          "     surface / Phong = %.2fx\n",
          ratio(p.licDefaultCpuMs, ours.fabricCpuMs), ratio(p.licDefaultCpuMs, ours.movingCpuMs),
          ratio(p.licOneStepCpuMs, ours.fabricCpuMs),
          ratio(p.surfaceCpuMs, ours.phongCpuMs));
  }
  if (!p.png.empty()) std::printf("  one frame of its default LIC: %s\n", p.png.c_str());
}

void addRenderPeerJson(nlohmann::ordered_json& j, const RenderPeerResult& p, const RenderPeerOurs& ours) {
  if (!p.ran) {
    j["peer"] = nullptr;
    j["peer_note"] = p.note;
    return;
  }
  double load = -1; // 1-minute load average when the peer finished
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = -1;
    std::fclose(f);
  }
  auto ratio = [](double a, double b) { return a > 0 && b > 0 ? a / b : 0.0; };
  j["peer"] = {{"name", p.name},
               {"case", "sphere_41k"},
               {"frames", p.frames},
               {"coverage", p.coverage},
               {"lic_default_steps", p.licDefaultSteps},
               {"lic_default_ms", p.licDefaultMs},
               {"lic_one_step_ms", p.licOneStepMs},
               {"surface_ms", p.surfaceMs},
               {"lic_default_cpu_ms", p.licDefaultCpuMs},
               {"lic_one_step_cpu_ms", p.licOneStepCpuMs},
               {"surface_cpu_ms", p.surfaceCpuMs},
               {"default_over_fabric", ratio(p.licDefaultMs, ours.fabricMs)},
               {"default_over_moving", ratio(p.licDefaultMs, ours.movingMs)},
               {"default_over_fabric_cpu", ratio(p.licDefaultCpuMs, ours.fabricCpuMs)},
               {"default_over_moving_cpu", ratio(p.licDefaultCpuMs, ours.movingCpuMs)},
               {"load_average", load}};
}

} // namespace dtf::app
