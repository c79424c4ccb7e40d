// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench render`: GPU time per fabric pass and ms/frame of the fabric against plain Phong of the
// same mesh and camera, in the paper's Table 1 setting (1024x768, about 3/4 of the pixels covered, one
// frame = projection + silhouette + 3 advection iterations + composite), on UV spheres of about 41k and
// 572k triangles with an anisotropic Hessian field, and on the real brain's FA 0.25 isosurface when the
// shared data is there. The "embedded" case draws the 41k sphere the way a host application would: its own
// raw GL pass of the sphere's depth and world normals, then EmbeddedFabric::draw into its framebuffer, next
// to the own front end on the same camera.
#include "app/bench/bench.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "render/embedding.h"
#include "render/fabric_renderer.h"
#include "render/gl_context.h"
#include "render/reference/scenes.h"
#include "ui/session/surface_spec.h"
#include "io/formats/json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>
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

// Frames of two kinds timed against each other (interleave): the fabric's and Phong's, or the fabric's in
// two variants. Per frame means of each kind, and the first / second ratios per block as medians with the
// CPU range.
struct Interleaved {
  double fabricMs = 0, fabricCpuMs = 0, phongMs = 0, phongCpuMs = 0;
  double wallRatio = 0, cpuRatio = 0, cpuRatioLo = 0, cpuRatioHi = 0;
  int blocks = 0;
};

struct Result {
  std::string name;
  std::size_t triangles = 0;
  double coverage = 0;
  // Fabric frames against Phong frames of the same camera, interleaved (see interleave): the still camera,
  // the moving one at full resolution, and the moving one at half internal resolution (as the viewer draws
  // it) against full-resolution Phong.
  Interleaved still, moving, half;
  render::PassTimes movingPasses;         // GPU: the moving camera's passes (the projection runs every frame)
  render::PassTimes passes;
  int frames = 0;
  render::Camera camera; // the camera of the static frames
  // The still frames ran their last iteration in the composite's pass (FabricRenderer::setFusedComposite),
  // and that pass's CPU time against the separate passes in the same run (compareFusion).
  bool fused = false;
  struct Fusion {
    int pairs = 0;
    double median = 0, lo = 0, hi = 0; // fused / separate, CPU time of the same still frames
  } fusion;
};

// The host route on the same sphere and camera: the host's geometry pass plus EmbeddedFabric::draw.
struct EmbeddedResult {
  bool ran = false;
  double ms = 0, movingMs = 0, cpuMs = 0; // per frame, host pass included
  double hostPassMs = 0;                  // GPU: the host's depth + normal pass
  double hostOnlyMs = 0, hostOnlyCpuMs = 0; // the host's pass alone per frame (wall, CPU time)
  render::PassTimes passes;               // GPU: EmbeddedFabric's passes (projection = import + tensor stage)
};

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double cpuMsSince(std::clock_t c0) { return 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC; }

// `frames` frames of `fabric` in blocks of `block`, each block followed by as many frames of `phong`, so a
// change in other processes' load falls on both alike.
template <class FabricFrame, class PhongFrame>
Interleaved interleave(int frames, int block, FabricFrame&& fabric, PhongFrame&& phong) {
  Interleaved r;
  std::vector<double> wallRatios, cpuRatios;
  for (int done = 0; done < frames; done += block) {
    const int n = std::min(block, frames - done);
    double wall[2], cpu[2];
    for (int kind = 0; kind < 2; ++kind) {
      const std::clock_t c0 = std::clock();
      const auto t0 = std::chrono::steady_clock::now();
      for (int f = 0; f < n; ++f) {
        if (kind == 0)
          fabric();
        else
          phong();
      }
      glFinish();
      wall[kind] = msSince(t0);
      cpu[kind] = cpuMsSince(c0);
    }
    r.fabricMs += wall[0];
    r.fabricCpuMs += cpu[0];
    r.phongMs += wall[1];
    r.phongCpuMs += cpu[1];
    wallRatios.push_back(wall[0] / std::max(wall[1], 1e-9));
    cpuRatios.push_back(cpu[0] / std::max(cpu[1], 1e-9));
  }
  r.fabricMs /= frames;
  r.fabricCpuMs /= frames;
  r.phongMs /= frames;
  r.phongCpuMs /= frames;
  r.blocks = static_cast<int>(cpuRatios.size());
  r.wallRatio = median(wallRatios);
  r.cpuRatio = median(cpuRatios);
  r.cpuRatioLo = *std::min_element(cpuRatios.begin(), cpuRatios.end());
  r.cpuRatioHi = *std::max_element(cpuRatios.begin(), cpuRatios.end());
  return r;
}

void accumulate(render::PassTimes& sum, const render::PassTimes& t) {
  sum.projection += t.projection;
  sum.silhouette += t.silhouette;
  sum.advection += t.advection;
  sum.composite += t.composite;
}

// The fabric passes' mean per frame (phong 0: timed separately).
render::PassTimes averaged(const render::PassTimes& sum, int frames) {
  return {sum.projection / frames, sum.silhouette / frames, sum.advection / frames, sum.composite / frames, 0};
}

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
  c.mesh = session::buildSurface(session::parseSurfaceSpec("fa=0.25"), c.field, fa);
  return c;
}

// Still frames with the last iteration fused into the composite against the same frames in separate passes
// (the same images): `pairs` pairs of two-frame blocks, alternating, continuing one state; the CPU time
// ratio's median and range over the pairs. Leaves the renderer fusing.
Result::Fusion compareFusion(render::FabricRenderer& r, const render::Camera& cam, const render::FabricParams& p,
                             int pairs) {
  auto frame = [&](bool fused) {
    r.setFusedComposite(fused);
    r.renderFrame(cam, p);
  };
  const Interleaved t = interleave(
      2 * pairs, 2, [&] { frame(true); }, [&] { frame(false); });
  r.setFusedComposite(true);
  return {t.blocks, t.cpuRatio, t.cpuRatioLo, t.cpuRatioHi};
}

Result runCase(render::FabricRenderer& r, const Case& c, int width, int height, int frames, render::ColourMode mode,
               bool fuse) {
  Result res;
  res.name = c.name;
  res.triangles = c.mesh.triangleCount();
  res.frames = frames;
  r.setFusedComposite(fuse);
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
  res.camera = cam;
  // Static camera: the paper's frame (projection, silhouette, 3 advections, composite), state carried on,
  // against plain Phong of the same mesh and camera. The two alternate in blocks of a few frames (Phong on a
  // renderer of its own, so the fabric's state carries on between its blocks): a change in other processes'
  // load falls on both alike, and the ratios are the medians over the blocks.
  render::FabricRenderer phong;
  phong.setMesh(c.mesh);
  phong.resize(width, height);
  phong.renderPhong(cam); // warm: program, targets
  glFinish();
  constexpr int kBlock = 2;
  r.setTiming(true);
  phong.setTiming(true);
  render::PassTimes sum;
  double phongGpu = 0;
  res.still = interleave(
      frames, kBlock,
      [&] {
        r.renderFrame(cam, p);
        accumulate(sum, r.lastTimes()); // waits for the frame
      },
      [&] {
        phong.renderPhong(cam);
        phongGpu += phong.lastTimes().phong; // waits for the frame
      });
  phong.setTiming(false);
  res.passes = averaged(sum, frames);
  res.passes.phong = phongGpu / frames;
  res.fused = r.lastFrameFused();
  if (res.fused) res.fusion = compareFusion(r, cam, p, std::max(frames, 20));
  // Moving camera: a small trackball step every frame; the projection and silhouettes run every frame and
  // the advection restarts from beta each frame. Its blocks alternate with Phong blocks of the same camera as
  // the still ones do, so the moving ratio resists other processes' load as the still ratio does.
  render::PassTimes movingSum;
  render::Camera moving = cam;
  res.moving = interleave(
      frames, kBlock,
      [&] {
        moving.trackball({0.0, 0.0}, {0.01, 0.0});
        r.renderFrame(moving, p);
        accumulate(movingSum, r.lastTimes()); // waits for the frame
      },
      [&] { phong.renderPhong(moving); });
  res.movingPasses = averaged(movingSum, frames);
  r.setTiming(false);
  // The same at half internal resolution while moving (FabricParams::movingScale), as the viewer draws a
  // moving camera (its interactive scale is at most 1/2), against full-resolution Phong.
  render::FabricParams half = p;
  half.movingScale = 0.5;
  res.half = interleave(
      frames, kBlock,
      [&] {
        moving.trackball({0.0, 0.0}, {0.01, 0.0});
        r.renderFrame(moving, half);
      },
      [&] { phong.renderPhong(moving); });
  render::checkGl("bench render " + c.name);
  return res;
}


// A host application's own scene, in raw GL as such a program would write it: the mesh in its own buffers
// and program, a G-buffer (world normals RGBA16F + depth) and a display framebuffer (colour + the same depth).
class HostScene {
public:
  HostScene(const Mesh& mesh, int width, int height) : width_(width), height_(height) {
    const char* vs = "#version 450 core\n"
                     "layout(location = 0) in vec3 a_position;\n"
                     "layout(location = 1) in vec3 a_normal;\n"
                     "uniform mat4 u_viewProj;\n"
                     "out vec3 v_normal;\n"
                     "void main() { v_normal = a_normal; gl_Position = u_viewProj * vec4(a_position, 1.0); }\n";
    const char* fs = "#version 450 core\n"
                     "in vec3 v_normal;\n"
                     "layout(location = 0) out vec4 o_normal;\n"
                     "void main() { o_normal = vec4(normalize(v_normal), 1.0); }\n";
    program_ = glCreateProgram();
    for (auto [stage, src] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
      GLuint sh = glCreateShader(stage);
      glShaderSource(sh, 1, &src, nullptr);
      glCompileShader(sh);
      glAttachShader(program_, sh);
      glDeleteShader(sh);
    }
    glLinkProgram(program_);
    GLint linked = 0;
    glGetProgramiv(program_, GL_LINK_STATUS, &linked);
    if (!linked) throw GlError("bench render: the host's program does not link");
    Mesh m = mesh;
    if (m.normals.size() != m.positions.size()) m.computeNormals();
    glCreateBuffers(3, buffers_);
    glNamedBufferStorage(buffers_[0], static_cast<GLsizeiptr>(m.positions.size() * sizeof(glm::vec3)),
                         m.positions.data(), 0);
    glNamedBufferStorage(buffers_[1], static_cast<GLsizeiptr>(m.normals.size() * sizeof(glm::vec3)), m.normals.data(), 0);
    glNamedBufferStorage(buffers_[2], static_cast<GLsizeiptr>(m.indices.size() * sizeof(std::uint32_t)),
                         m.indices.data(), 0);
    indexCount_ = static_cast<GLsizei>(m.indices.size());
    glCreateVertexArrays(1, &vao_);
    for (GLuint a = 0; a < 2; ++a) {
      glVertexArrayVertexBuffer(vao_, a, buffers_[a], 0, sizeof(glm::vec3));
      glVertexArrayAttribFormat(vao_, a, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(vao_, a, a);
      glEnableVertexArrayAttrib(vao_, a);
    }
    glVertexArrayElementBuffer(vao_, buffers_[2]);
    glCreateTextures(GL_TEXTURE_2D, 3, textures_);
    glTextureStorage2D(textures_[0], 1, GL_DEPTH_COMPONENT32F, width, height);
    glTextureStorage2D(textures_[1], 1, GL_RGBA16F, width, height);
    glTextureStorage2D(textures_[2], 1, GL_RGBA8, width, height);
    glCreateFramebuffers(2, fbos_);
    glNamedFramebufferTexture(fbos_[0], GL_COLOR_ATTACHMENT0, textures_[1], 0);
    glNamedFramebufferTexture(fbos_[0], GL_DEPTH_ATTACHMENT, textures_[0], 0);
    glNamedFramebufferTexture(fbos_[1], GL_COLOR_ATTACHMENT0, textures_[2], 0);
    glNamedFramebufferTexture(fbos_[1], GL_DEPTH_ATTACHMENT, textures_[0], 0);
    glCreateQueries(GL_TIME_ELAPSED, 1, &timer_);
  }
  ~HostScene() {
    glDeleteQueries(1, &timer_);
    glDeleteFramebuffers(2, fbos_);
    glDeleteTextures(3, textures_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(3, buffers_);
    glDeleteProgram(program_);
  }
  HostScene(const HostScene&) = delete;
  HostScene& operator=(const HostScene&) = delete;

  // The host's geometry pass of one frame (timed with a GL_TIME_ELAPSED query), then its display
  // framebuffer cleared to black; returns the view EmbeddedFabric::draw takes.
  render::HostView frame(const glm::mat4& view, const glm::mat4& projection) {
    glBeginQuery(GL_TIME_ELAPSED, timer_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbos_[0]);
    glViewport(0, 0, width_, height_);
    const float zero[4] = {0, 0, 0, 0}, one = 1.0f;
    glClearNamedFramebufferfv(fbos_[0], GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(fbos_[0], GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE); // a closed sphere seen from outside, as any host would draw it
    glUseProgram(program_);
    glProgramUniformMatrix4fv(program_, glGetUniformLocation(program_, "u_viewProj"), 1, GL_FALSE,
                              &(projection * view)[0][0]);
    glBindVertexArray(vao_);
    glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_CULL_FACE);
    glEndQuery(GL_TIME_ELAPSED);
    glClearNamedFramebufferfv(fbos_[1], GL_COLOR, 0, zero);
    render::HostView v;
    v.depthTexture = textures_[0];
    v.normalTexture = textures_[1];
    v.view = view;
    v.projection = projection;
    v.viewport = {0, 0, width_, height_};
    v.framebuffer = fbos_[1];
    return v;
  }
  double lastPassMs() const {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer_, GL_QUERY_RESULT, &ns);
    return static_cast<double>(ns) * 1e-6;
  }

private:
  int width_, height_;
  GLuint program_ = 0, vao_ = 0, buffers_[3] = {0, 0, 0}, textures_[3] = {0, 0, 0}, fbos_[2] = {0, 0}, timer_ = 0;
  GLsizei indexCount_ = 0;
};

EmbeddedResult runEmbedded(const Case& c, const render::Camera& camera, int width, int height, int frames,
                           render::ColourMode mode, bool computePasses) {
  EmbeddedResult res;
  res.ran = true;
  HostScene host(c.mesh, width, height);
  render::EmbeddedFabric fabric;
  fabric.setComputePasses(computePasses);
  fabric.setField(c.field);
  render::FabricParams p;
  p.iterations = 3;
  p.colour = mode;
  const double aspect = double(width) / height;
  const glm::mat4 view(camera.view()), projection(camera.projection(aspect));
  fabric.draw(host.frame(view, projection), p); // warm-up: programs, noise, targets
  glFinish();
  fabric.setTiming(true);
  render::PassTimes sum;
  double hostSum = 0;
  std::clock_t c0 = std::clock();
  auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    fabric.draw(host.frame(view, projection), p);
    render::PassTimes t = fabric.lastTimes(); // waits for the frame
    hostSum += host.lastPassMs();
    accumulate(sum, t);
  }
  glFinish();
  res.ms = msSince(t0) / frames;
  res.cpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / frames;
  res.hostPassMs = hostSum / frames;
  res.passes = averaged(sum, frames);
  fabric.setTiming(false);
  // Moving camera: the same trackball steps as the own front end's moving figure.
  render::Camera moving = camera;
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    moving.trackball({0.0, 0.0}, {0.01, 0.0});
    fabric.draw(host.frame(glm::mat4(moving.view()), projection), p);
    glFinish();
  }
  res.movingMs = msSince(t0) / frames;
  // The host's pass alone: what the host pays without the fabric.
  c0 = std::clock();
  t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    host.frame(view, projection);
    glFinish();
  }
  res.hostOnlyMs = msSince(t0) / frames;
  res.hostOnlyCpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / frames;
  render::checkGl("bench render embedded " + c.name);
  return res;
}

// The figure look's costs on the real brain's middle axial slice, static camera, fabric frames as above:
// today's fabric (plain look, the slice clipped to whole voxels of data), the smooth data edge (the cells the
// edge crosses kept, the cover ramp drawn), the anatomy look over a background volume (FA on the data's grid,
// sampled per fragment), and a 2x supersampled still's frame (4x the pixels) plus its box filter on the CPU.
struct LookResult {
  std::string name;
  double ms = 0, cpuMs = 0; // per frame
};

std::vector<LookResult> runLooks(render::FabricRenderer& r, const TensorField& field, int width, int height,
                                 int frames) {
  std::vector<LookResult> out;
  const ScalarVolume fa = computeFaMap(field);
  session::SurfaceBuildOptions lattice, smooth;
  smooth.dataEdgeCells = true;
  const session::SurfaceSpec spec = session::parseSurfaceSpec("slice=axial");
  const Mesh latticeMesh = session::buildSurface(spec, field, fa, lattice);
  const Mesh smoothMesh = session::buildSurface(spec, field, fa, smooth);
  r.setField(field);
  glm::vec3 lo, hi;
  latticeMesh.bounds(lo, hi);
  const render::Camera cam =
      render::Camera::standard(render::StandardView::Inferior, lo, hi, double(width) / height);
  auto timed = [&](const std::string& name, const Mesh& mesh, const render::FabricParams& p, int scale) {
    r.setMesh(mesh);
    r.resize(width * scale, height * scale);
    r.renderFrame(cam, p); // warm: programs, targets
    glFinish();
    std::clock_t c0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) {
      r.renderFrame(cam, p);
      if (scale > 1) {
        // The supersampled still's filter: read back and box-filter down on the CPU, as `render` does.
        const Image big = r.readback();
        Image small(width, height);
        for (int y = 0; y < height; ++y)
          for (int x = 0; x < width; ++x)
            for (int c = 0; c < 4; ++c) {
              int sum = 0;
              for (int dy = 0; dy < scale; ++dy)
                for (int dx = 0; dx < scale; ++dx)
                  sum += big.pixel(x * scale + dx, y * scale + dy)[c];
              small.pixel(x, y)[c] = static_cast<std::uint8_t>(sum / (scale * scale));
            }
      }
      glFinish();
    }
    out.push_back({name, msSince(t0) / frames, 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC / frames});
  };
  render::FabricParams plain;
  plain.look = render::Look::Plain;
  r.setBackground(nullptr);
  timed("plain_lattice_edge", latticeMesh, plain, 1);
  timed("plain_smooth_edge", smoothMesh, plain, 1);
  render::FabricParams anatomy;
  timed("anatomy_fa_beneath", smoothMesh, anatomy, 1);
  r.setBackground(&fa, 0.0f, 1.0f);
  timed("anatomy_background", smoothMesh, anatomy, 1);
  r.setBackground(nullptr);
  render::FabricParams two = anatomy;
  two.stepPixels *= 2;
  two.autoLodPixels *= 2;
  two.silhouettePixels *= 2;
  timed("anatomy_supersample2", smoothMesh, two, 2);
  r.resize(width, height);
  return out;
}

} // namespace

const OptionTable& benchRenderOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const RenderPeerOptions d; // the peer's defaults: the same size and frames
    OptionTable t;
    t.command = "bench render";
    t.intro =
        "Fabric frames (projection + silhouette + 3 advection iterations + composite, paper Table 1) against\n"
        "plain Phong of the same mesh and camera, about 3/4 of the pixels covered; GPU times per pass from\n"
        "GL_TIME_ELAPSED queries, ms/frame from the wall clock, CPU time of the process. Still camera: the\n"
        "projection and silhouettes of the previous frame are reused, and its frames alternate with Phong\n"
        "frames in blocks of two: the still ratios are medians over the blocks, robust to other processes'\n"
        "load; moving camera: every pass every frame, alternating with Phong the same way.\n"
        "With sphere_41k also the embedded case: a host's raw GL depth + normal pass of the same sphere and\n"
        "camera, then EmbeddedFabric::draw into the host's framebuffer (render/embedding.h).\n"
        "Peer on sphere_41k when pvbatch is on the PATH (Debian package paraview): ParaView's Surface LIC with\n"
        "its defaults and with 1 step, and its plain surface.";
    t.options = {
        O::text("size", "WxH", "image size", std::to_string(d.width) + "x" + std::to_string(d.height))
            .checkedBy(checkSize),
        O::integer("frames", "N", d.frames, closedRange(1, 1000), "timed frames per figure"),
        O::flag("json", "one JSON object"),
        O::flag("no-brain", "skip the real brain's FA 0.25 isosurface"),
        sharedDataOption(),
        O::choice("color", "C", {"medical", "engineering"}, "medical", "colour mode of the fabric"),
        O::text("only", "CASE[,CASE...]",
                "run only these cases: sphere_41k, sphere_41k_fibres3, sphere_572k, brain_fa025, looks (the "
                "figure look's costs on the brain's axial slice)")
            .defaultSays("all"),
        O::flag("no-peer", "skip ParaView's Surface LIC"),
        O::integer("peer-frames", "N", d.frames, closedRange(1, 1000), "timed frames per peer mode")
            .defaultSays("min(--frames, " + std::to_string(d.frames) + ")"),
        O::text("peer-png", "FILE", "save one of the peer's default LIC frames as PNG"),
        O::flag("no-fuse", "the frames' last advection iteration in a pass of its own before the composite "
                           "(by default fragment passes at full resolution run it in the composite's pass)"),
        O::choice("passes", "K", {"auto", "fragment", "compute"}, "auto",
                  "the tensor stage and the advection iterations as fullscreen draws or as compute shaders "
                  "(auto: compute on a hardware GPU, fragment on a software rasteriser)"),
    };
    return t;
  }();
  return table;
}

namespace {

// What one run measured, for the report.
struct Report {
  std::string renderer;
  int width = 0, height = 0, frames = 0;
  bool computePasses = false;
  std::vector<Result> results;
  EmbeddedResult embedded;
  RenderPeerResult peer;
  RenderPeerOurs mine;
  std::vector<LookResult> looks; // empty: the real brain was not there
};

void printJson(const Report& rep) {
  const std::string& renderer = rep.renderer;
  const int width = rep.width, height = rep.height, frames = rep.frames;
  const auto& results = rep.results;
  const auto& embedded = rep.embedded;
  const auto& peer = rep.peer;
  const auto& mine = rep.mine;
  using Json = nlohmann::ordered_json;
  Json j = {{"renderer", renderer}, {"width", width}, {"height", height}, {"frames", frames},
            {"passes", rep.computePasses ? "compute" : "fragment"}};
  Json cases = Json::array();
  for (const Result& r : results)
    cases.push_back({{"name", r.name},
                     {"triangles", r.triangles},
                     {"fabric_ms", r.still.fabricMs},
                     {"phong_ms", r.still.phongMs},
                     {"moving_ms", r.moving.fabricMs},
                     {"moving_half_res_ms", r.half.fabricMs},
                     {"fabric_cpu_ms", r.still.fabricCpuMs},
                     {"moving_cpu_ms", r.moving.fabricCpuMs},
                     {"phong_cpu_ms", r.still.phongCpuMs},
                     {"ratio", r.still.wallRatio},
                     {"cpu_ratio", r.still.cpuRatio},
                     {"cpu_ratio_range", {r.still.cpuRatioLo, r.still.cpuRatioHi}},
                     {"interleaved_blocks", r.still.blocks},
                     {"moving_phong_cpu_ms", r.moving.phongCpuMs},
                     {"moving_ratio", r.moving.wallRatio},
                     {"moving_cpu_ratio", r.moving.cpuRatio},
                     {"moving_cpu_ratio_range", {r.moving.cpuRatioLo, r.moving.cpuRatioHi}},
                     {"moving_half_res_cpu_ms", r.half.fabricCpuMs},
                     {"moving_half_res_phong_cpu_ms", r.half.phongCpuMs},
                     {"moving_half_res_ratio", r.half.wallRatio},
                     {"moving_half_res_cpu_ratio", r.half.cpuRatio},
                     {"moving_half_res_cpu_ratio_range", {r.half.cpuRatioLo, r.half.cpuRatioHi}},
                     {"coverage", r.coverage},
                     {"fused", r.fused},
                     {"fused_over_separate_cpu", r.fused ? Json{{"median", r.fusion.median},
                                                                {"range", {r.fusion.lo, r.fusion.hi}},
                                                                {"pairs", r.fusion.pairs}}
                                                         : Json(nullptr)},
                     {"passes_ms",
                      {{"projection", r.passes.projection},
                       {"silhouette", r.passes.silhouette},
                       {"advection", r.passes.advection},
                       {"composite", r.passes.composite},
                       {"phong", r.passes.phong}}}});
  j["cases"] = cases;
  if (embedded.ran)
    j["embedded"] = {{"name", "sphere_41k"},
                     {"embedded_ms", embedded.ms},
                     {"embedded_moving_ms", embedded.movingMs},
                     {"embedded_cpu_ms", embedded.cpuMs},
                     {"host_pass_ms", embedded.hostOnlyMs},
                     {"host_pass_cpu_ms", embedded.hostOnlyCpuMs},
                     {"own_ms", results[0].still.fabricMs},
                     {"own_cpu_ms", results[0].still.fabricCpuMs},
                     {"own_moving_ms", results[0].moving.fabricMs},
                     {"passes_ms",
                      {{"host_geometry", embedded.hostPassMs},
                       {"projection", embedded.passes.projection},
                       {"silhouette", embedded.passes.silhouette},
                       {"advection", embedded.passes.advection},
                       {"composite", embedded.passes.composite}}}};
  else
    j["embedded"] = nullptr;
  addRenderPeerJson(j, peer, mine);
  Json looks = Json::array();
  for (const auto& l : rep.looks)
    looks.push_back({{"name", l.name}, {"ms", l.ms}, {"cpu_ms", l.cpuMs}});
  j["looks"] = looks;
  std::printf("%s\n", io::jsonText(j).c_str());
}

void printTable(const Report& rep) {
  const std::string& renderer = rep.renderer;
  const int width = rep.width, height = rep.height, frames = rep.frames;
  const auto& results = rep.results;
  const auto& embedded = rep.embedded;
  const auto& peer = rep.peer;
  const auto& mine = rep.mine;
  double load = -1;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = -1;
    std::fclose(f);
  }
  std::printf("dtfabric bench render: %dx%d, %d frames per figure, %s, load average %.1f on %u cores\n", width, height,
              frames, renderer.c_str(), load, std::thread::hardware_concurrency());
  std::printf("frame = projection + silhouette + 3 advection iterations + composite (paper Table 1); goal fabric <= 95 ms\n");
  std::printf("tensor stage and advection: %s\n", rep.computePasses ? "compute shaders" : "fullscreen fragment passes");
  const bool anyFused = std::any_of(results.begin(), results.end(), [](const Result& r) { return r.fused; });
  std::printf("%s\n\n", anyFused ? "the last iteration runs in the composite's pass (GPU ms: advect3 holds the first two "
                                    "iterations, compos the third with the composite)"
                                  : "every iteration in a pass of its own, then the composite");
  std::printf("%-18s %9s %6s | %9s %9s %9s %9s %6s | GPU ms: %8s %8s %8s %8s %8s\n", "case", "triangles", "cover",
              "fabric", "moving", "mov 1/2", "phong", "ratio", "project", "silhou", "advect3", "compos", "phong");
  for (const Result& r : results)
    std::printf(
        "%-18s %9zu %5.0f%% | %6.1f ms %6.1f ms %6.1f ms %6.1f ms %6.2f | %16.2f %8.2f %8.2f %8.2f %8.2f\n",
        r.name.c_str(), r.triangles, 100 * r.coverage, r.still.fabricMs, r.moving.fabricMs, r.half.fabricMs,
        r.still.phongMs, r.still.wallRatio, r.passes.projection, r.passes.silhouette, r.passes.advection,
        r.passes.composite, r.passes.phong);
  // On a software rasteriser the process CPU time is the robust second figure (other processes' load inflates
  // wall times); on a GPU the CPU only submits, and the summed GPU pass times are.
  const std::string& rendererName = renderer;
  const bool software = rendererName.find("llvmpipe") != std::string::npos ||
                        rendererName.find("softpipe") != std::string::npos;
  const char* second = software ? "CPU time" : "GPU time";
  auto fabricGpu = [](const render::PassTimes& t) { return t.projection + t.silhouette + t.advection + t.composite; };
  // The still fabric / Phong ratio by the second figure: on a software rasteriser the median over the
  // interleaved blocks.
  auto stillSecondRatio = [&](const Result& r) {
    return software ? r.still.cpuRatio : fabricGpu(r.passes) / std::max(r.passes.phong, 1e-9);
  };
  std::printf("\nmoving camera, GPU ms per pass (the projection and silhouettes run every frame; silhou: the\n"
              "silhouettes found by the restart from beta, one pass):\n");
  for (const Result& r : results)
    std::printf("  %-18s project %8.2f  silhou %8.2f  advect3 %8.2f  compos %8.2f\n", r.name.c_str(),
                r.movingPasses.projection, r.movingPasses.silhouette, r.movingPasses.advection,
                r.movingPasses.composite);
  // The moving fabric / Phong ratio by the second figure: on a software rasteriser the median over the
  // interleaved blocks, on a GPU the passes' GPU times.
  auto movingSecondRatio = [&](const Result& r) {
    return software ? r.moving.cpuRatio : fabricGpu(r.movingPasses) / std::max(r.passes.phong, 1e-9);
  };
  if (software) {
    std::printf("\nCPU time per frame (all llvmpipe threads; less sensitive to other processes' load):\n");
    for (const Result& r : results)
      std::printf("  %-18s still %7.1f ms  moving %7.1f ms  phong %6.1f ms  -> uncontended on %u cores about "
                  "%.0f / %.0f / %.0f ms\n",
                  r.name.c_str(), r.still.fabricCpuMs, r.moving.fabricCpuMs, r.still.phongCpuMs,
                  std::thread::hardware_concurrency(),
                  r.still.fabricCpuMs / std::max(1u, std::thread::hardware_concurrency()),
                  r.moving.fabricCpuMs / std::max(1u, std::thread::hardware_concurrency()),
                  r.still.phongCpuMs / std::max(1u, std::thread::hardware_concurrency()));
  }
  std::printf("\nfabric/Phong ratio, paper Table 1 (GPU, 2010): 1.9 on the 41k sphere, 1.14 on the 572k sphere.\n"
              "still: the static camera's frames (the projection and silhouettes of the previous frame are reused,\n"
              "3 advection iterations + composite), alternating with Phong in blocks of 2 frames, the median over\n"
              "the blocks (range); moving: a trackball step per frame (the whole frame), its blocks alternating\n"
              "with Phong blocks of the same camera in the same way.\n");
  for (const Result& r : results) {
    std::printf("  %-18s still %.2f wall, %.2f %s", r.name.c_str(), r.still.wallRatio, stillSecondRatio(r),
                second);
    if (software)
      std::printf(" (%.2f-%.2f over %d blocks)", r.still.cpuRatioLo, r.still.cpuRatioHi, r.still.blocks);
    std::printf(" | moving %.2f wall, %.2f %s", r.moving.wallRatio, movingSecondRatio(r), second);
    if (software) std::printf(" (%.2f-%.2f)", r.moving.cpuRatioLo, r.moving.cpuRatioHi);
    std::printf("\n");
  }
  std::printf("\nmoving as the viewer draws it: the fabric at 1/2 internal resolution (the viewer's largest\n"
              "interactive scale), upscaled, against full-resolution Phong, interleaved the same way:\n");
  for (const Result& r : results) {
    std::printf("  %-18s 1/2 %.2f wall", r.name.c_str(), r.half.wallRatio);
    if (software)
      std::printf(", %.2f CPU time (%.2f-%.2f)", r.half.cpuRatio, r.half.cpuRatioLo, r.half.cpuRatioHi);
    std::printf("\n");
  }
  const Result* two = nullptr;
  const Result* three = nullptr;
  for (const Result& r : results) {
    if (r.name == "sphere_41k") two = &r;
    if (r.name == "sphere_41k_fibres3") three = &r;
  }
  // The quotient of the two cases' fabric/Phong ratios, each over the Phong frames it alternated with (the
  // same sphere's Phong), so a load change between the two cases cancels.
  if (two && three)
    std::printf(
        "\nthree fibre populations vs the two-direction tensor fabric on the 41k sphere (goal <= 1.5):\n"
        "  still %.2f wall, %.2f %s | moving %.2f wall, %.2f %s\n",
        three->still.wallRatio / std::max(two->still.wallRatio, 1e-9),
        stillSecondRatio(*three) / std::max(stillSecondRatio(*two), 1e-9), second,
        three->moving.wallRatio / std::max(two->moving.wallRatio, 1e-9),
        movingSecondRatio(*three) / std::max(movingSecondRatio(*two), 1e-9), second);
  if (std::any_of(results.begin(), results.end(), [](const Result& r) { return r.fused; })) {
    std::printf("\nthe last iteration in the composite's pass against separate passes, the same still frames in\n"
                "the same run (CPU time, fused / separate: median over pairs of 2-frame blocks, range):\n");
    for (const Result& r : results)
      if (r.fused)
        std::printf("  %-18s %.3f (%.2f-%.2f over %d pairs)\n", r.name.c_str(), r.fusion.median, r.fusion.lo,
                    r.fusion.hi, r.fusion.pairs);
  }
  if (embedded.ran) {
    // The embedded route projects every frame (the host may redraw its buffers with the same camera), so
    // it compares with the own front end's moving frames, which project every frame too.
    const Result& own = results[0];
    std::printf("\nembedded on sphere_41k (a host's raw GL depth + normal pass, then EmbeddedFabric::draw into its\n"
                "framebuffer; same camera; it projects every frame) against the own front end's moving frames\n"
                "(FabricRenderer::renderFrame, projecting every frame):\n");
    std::printf("  %-9s %8s %8s %8s | GPU ms: %8s %8s %8s %8s %8s\n", "route", "static", "moving", "CPU", "geometry",
                "project", "silhou", "advect3", "compos");
    std::printf("  %-9s %8s %5.1f ms %5.1f ms | %16s %8.2f %8.2f %8.2f %8.2f\n", "own", "",
                own.moving.fabricMs, own.moving.fabricCpuMs, "(in project)", own.movingPasses.projection,
                own.movingPasses.silhouette, own.movingPasses.advection, own.movingPasses.composite);
    std::printf("  %-9s %5.1f ms %5.1f ms %5.1f ms | %16.2f %8.2f %8.2f %8.2f %8.2f\n", "embedded", embedded.ms,
                embedded.movingMs, embedded.cpuMs, embedded.hostPassMs, embedded.passes.projection,
                embedded.passes.silhouette, embedded.passes.advection, embedded.passes.composite);
    std::printf("  %-9s %5.1f ms %8s %5.1f ms   (the host's depth + normal pass alone)\n", "host pass",
                embedded.hostOnlyMs, "", embedded.hostOnlyCpuMs);
    // GPU: the host's pass is `geometry`; EmbeddedFabric::draw alone is the passes after it.
    const double embeddedDraw = fabricGpu(embedded.passes), ownGpu = fabricGpu(own.movingPasses);
    const double withHost = software ? embedded.cpuMs / std::max(own.moving.fabricCpuMs, 1e-9)
                                     : (embedded.hostPassMs + embeddedDraw) / std::max(ownGpu, 1e-9);
    const double drawAlone =
        software ? (embedded.cpuMs - embedded.hostOnlyCpuMs) / std::max(own.moving.fabricCpuMs, 1e-9)
                 : embeddedDraw / std::max(ownGpu, 1e-9);
    std::printf(
        "  embedded / own: %.2f wall, %.2f %s, the host's pass included; without it (EmbeddedFabric::draw\n"
        "  alone) %.2f wall, %.2f %s (goal <= 1). The embedded project = import of the host's textures +\n"
        "  tensor stage, the own one = the mesh's geometry stage + tensor stage.\n",
        embedded.ms / std::max(own.moving.fabricMs, 1e-9), withHost, second,
        (embedded.ms - embedded.hostOnlyMs) / std::max(own.moving.fabricMs, 1e-9), drawAlone, second);
  }
  std::printf("\nfabric: static camera, advection state carried between frames, the projection and silhouettes of\n"
              "the previous frame reused (unchanged camera, data and parameters); moving: a trackball step per frame,\n"
              "the whole frame, the advection restarts from the mapped noise (no smearing); mov 1/2: the same with the fabric computed\n"
              "at half resolution while moving. Times are wall-clock ms/frame; CPU load from other processes inflates\n"
              "them (the load average is printed above).\n");
  printRenderPeerTable(peer, mine);
  if (!rep.looks.empty()) {
    std::printf("\nfigure look on the real brain's middle axial slice (radiological, static camera, frame as above;\n"
                "supersample2 = the frame at 2x the size plus the readback and box filter of a still):\n");
    const LookResult& base = rep.looks.front();
    for (const LookResult& l : rep.looks)
      std::printf("  %-22s %7.1f ms wall %7.1f ms CPU   x%.2f CPU of %s\n", l.name.c_str(), l.ms, l.cpuMs,
                  l.cpuMs / std::max(base.cpuMs, 1e-9), base.name.c_str());
  }
}
} // namespace

int benchRender(const CommandArgs& argv) {
  ParsedOptions args(benchRenderOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const bool json = args.flag("json");
  int width = 0, height = 0;
  parseSize(args.text("size"), width, height);
  const int frames = args.integer("frames");
  const bool noBrain = args.flag("no-brain");
  const auto mode =
      args.text("color") == "medical" ? render::ColourMode::Medical : render::ColourMode::Engineering;
  const std::string only = args.text("only");
  const auto dataDir = args.get("data");
  const bool noPeer = args.flag("no-peer");
  const int peerFrames =
      args.given("peer-frames") ? args.integer("peer-frames") : std::min(frames, RenderPeerOptions{}.frames);
  const std::string peerPng = args.text("peer-png");
  const std::string passes = args.text("passes");
  const bool fuse = !args.flag("no-fuse");
  args.finish();

  auto& ctx = render::GlContext::headless();
  render::FabricRenderer renderer;
  const bool computePasses = passes == "auto" ? renderer.computePasses() : passes == "compute";
  renderer.setComputePasses(computePasses);
  std::vector<Case> cases;
  cases.push_back(sphereCase("sphere_41k", 145, 144));   // 2 * 144 * 144 = 41472 triangles (Table 1, Fig. 8)
  cases.push_back(fibreSphereCase(cases.back()));        // three fibre populations on the same sphere
  cases.push_back(sphereCase("sphere_572k", 534, 536));  // 2 * 536 * 533 = 571376 triangles (Table 1, Fig. 7)
  if (!noBrain)
    if (auto b = brainCase(dataDir)) cases.push_back(std::move(*b));
  std::vector<Result> results;
  for (const auto& c : cases)
    if (only.empty() || ("," + only + ",").find("," + c.name + ",") != std::string::npos) results.push_back(runCase(renderer, c, width, height, frames, mode, fuse));
  // The host route on the same sphere and camera as the own front end's sphere_41k.
  EmbeddedResult embedded;
  if (!results.empty() && results[0].name == "sphere_41k")
    embedded = runEmbedded(cases[0], results[0].camera, width, height, frames, mode, computePasses);
  // The peer, ParaView's Surface LIC, on sphere_41k after ours (app/bench/bench_render_peer.cpp).
  const Result* ours = results.empty() || results[0].name != "sphere_41k" ? nullptr : &results[0];
  RenderPeerResult peer;
  peer.note = noPeer ? "skipped (--no-peer)" : "ParaView Surface LIC runs on sphere_41k only";
  if (!noPeer && ours)
    peer = runRenderPeer(cases[0].mesh, cases[0].field, {width, height, peerFrames, peerPng});
  const RenderPeerOurs mine =
      ours ? RenderPeerOurs{ours->still.fabricMs,    ours->moving.fabricMs,  ours->still.phongMs,
                            ours->still.fabricCpuMs, ours->still.phongCpuMs, ours->moving.fabricCpuMs}
           : RenderPeerOurs{};

  std::vector<LookResult> looks;
  if (!noBrain && (only.empty() || ("," + only + ",").find(",looks,") != std::string::npos))
    if (auto b = brainCase(dataDir)) looks = runLooks(renderer, b->field, width, height, frames);
  const Report report{ctx.description(), width, height, frames, computePasses, std::move(results), embedded, peer,
                      mine, std::move(looks)};
  if (json)
    printJson(report);
  else
    printTable(report);
  return 0;
}

} // namespace dtf::app
