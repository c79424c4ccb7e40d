// SPDX-License-Identifier: GPL-3.0-or-later
// A program outside dtfabric's source tree, built against the installed package (find_package(dtfabric)),
// that uses it the way a host application with its own GL context does:
//   1. makes its own headless EGL context (GL 4.5 core, no surface),
//   2. loads the real tensor volume with dtf::io::readTensorVolume and checks it against known values,
//   3. builds a sphere with the public API and draws its depth and world normals with raw GL into its own
//      framebuffer, with its own view and projection matrices,
//   4. sets GL state of its own, hands its depth and normal textures with its matrices to the embedding API
//      (dtf::render::EmbeddedFabric), which draws the fabric into the host's own colour + depth framebuffer,
//      and checks that its state is untouched afterwards,
//   5. compares the fabric image with a baseline and the depth the fabric wrote with its own.
// Usage: dtfabric_consumer SHARED_DATA_DIR BASELINE_PNG OUTPUT_DIR. Exit code 0 when every check passed.
// Prints "dtfabric_consumer: SKIPPED" and exits 0 when GL or the data is missing, unless DTF_REQUIRE_GL=1
// or DTF_REQUIRE_SHARED_DATA=1 (then it fails). DTF_UPDATE_BASELINES=1 rewrites the baseline.
#include <dtfabric/dtfabric.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

constexpr int kSize = 256;
int gFailures = 0;

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::string(v) != "0";
}

void check(bool ok, const std::string& what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAILED", what.c_str());
  if (!ok) ++gFailures;
}

bool near(double a, double b, double tol) { return std::abs(a - b) <= tol; }

// A missing context or data file: skipped, or a failure when `requireVar` is set.
[[noreturn]] void missing(const char* requireVar, const std::string& why) {
  if (envFlag(requireVar)) {
    std::fprintf(stderr, "dtfabric_consumer: FAILED: %s (%s is set)\n", why.c_str(), requireVar);
    std::exit(1);
  }
  std::printf("dtfabric_consumer: SKIPPED: %s\n", why.c_str());
  std::exit(0);
}

// ---- The host's own context: EGL, no config, no surface, GL 4.5 core ----

bool makeContext(std::string& why) {
  EGLDisplay dpy = EGL_NO_DISPLAY;
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (dpy == EGL_NO_DISPLAY) dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  EGLint major = 0, minor = 0;
  if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
    why = "no EGL display";
    return false;
  }
  if (!epoxy_has_egl_extension(dpy, "EGL_KHR_no_config_context") ||
      !epoxy_has_egl_extension(dpy, "EGL_KHR_surfaceless_context") || !eglBindAPI(EGL_OPENGL_API)) {
    why = "EGL display without configless/surfaceless OpenGL contexts";
    return false;
  }
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
    why = "cannot create and make current a GL 4.5 core context";
    return false;
  }
  if (epoxy_gl_version() < 45) {
    why = "context below GL 4.5";
    return false;
  }
  return true;
}

// ---- Raw GL of the host ----

GLuint compile(GLenum type, const char* source) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    std::fprintf(stderr, "host shader: %s\n", log);
    std::exit(1);
  }
  return s;
}

// Depth and world-space normal of the host's geometry: what an embedding host hands to dtfabric.
GLuint geometryProgram() {
  const char* vs = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_viewProj;
out vec3 v_normal;
void main() { v_normal = a_normal; gl_Position = u_viewProj * vec4(a_position, 1.0); })";
  const char* fs = R"(#version 450 core
in vec3 v_normal;
layout(location = 0) out vec4 o_normal;
void main() { o_normal = vec4(normalize(v_normal), 1.0); })";
  GLuint p = glCreateProgram();
  GLuint a = compile(GL_VERTEX_SHADER, vs), b = compile(GL_FRAGMENT_SHADER, fs);
  glAttachShader(p, a);
  glAttachShader(p, b);
  glLinkProgram(p);
  glDeleteShader(a);
  glDeleteShader(b);
  return p;
}

struct HostTargets {
  GLuint fbo = 0, normal = 0, depth = 0;
};

HostTargets makeTargets() {
  HostTargets t;
  glGenTextures(1, &t.normal);
  glBindTexture(GL_TEXTURE_2D, t.normal);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, kSize, kSize, 0, GL_RGBA, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenTextures(1, &t.depth);
  glBindTexture(GL_TEXTURE_2D, t.depth);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, kSize, kSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenFramebuffers(1, &t.fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.normal, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t.depth, 0);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    std::fprintf(stderr, "host framebuffer incomplete\n");
    std::exit(1);
  }
  return t;
}

// The GL state the host sets before calling dtfabric and expects back afterwards.
struct HostState {
  GLint program = 0, drawFbo = 0, readFbo = 0, vao = 0, arrayBuffer = 0, activeTexture = 0;
  std::array<GLint, 4> viewport{}, scissorBox{};
  std::array<GLint, 8> textures2d{};
  GLboolean depthTest = 0, blend = 0, cullFace = 0, scissorTest = 0, depthMask = 0;
  GLint depthFunc = 0, blendSrc = 0, blendDst = 0, packAlignment = 0, unpackAlignment = 0;
  std::array<GLfloat, 4> clearColour{};

  static HostState capture() {
    HostState s;
    glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.drawFbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s.readFbo);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s.vao);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &s.arrayBuffer);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &s.activeTexture);
    glGetIntegerv(GL_VIEWPORT, s.viewport.data());
    glGetIntegerv(GL_SCISSOR_BOX, s.scissorBox.data());
    for (int u = 0; u < int(s.textures2d.size()); ++u) {
      glActiveTexture(GLenum(GL_TEXTURE0 + u));
      glGetIntegerv(GL_TEXTURE_BINDING_2D, &s.textures2d[u]);
    }
    glActiveTexture(GLenum(s.activeTexture));
    s.depthTest = glIsEnabled(GL_DEPTH_TEST);
    s.blend = glIsEnabled(GL_BLEND);
    s.cullFace = glIsEnabled(GL_CULL_FACE);
    s.scissorTest = glIsEnabled(GL_SCISSOR_TEST);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depthMask);
    glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
    glGetIntegerv(GL_BLEND_SRC_RGB, &s.blendSrc);
    glGetIntegerv(GL_BLEND_DST_RGB, &s.blendDst);
    glGetIntegerv(GL_PACK_ALIGNMENT, &s.packAlignment);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &s.unpackAlignment);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s.clearColour.data());
    return s;
  }
};

void checkStateKept(const HostState& a, const HostState& b) {
  check(a.program == b.program, "host program still bound");
  check(a.drawFbo == b.drawFbo && a.readFbo == b.readFbo, "host draw and read framebuffers still bound");
  check(a.viewport == b.viewport, "host viewport kept");
  check(a.scissorBox == b.scissorBox, "host scissor box kept");
  check(a.vao == b.vao && a.arrayBuffer == b.arrayBuffer, "host vertex array and array buffer still bound");
  check(a.activeTexture == b.activeTexture, "host active texture unit kept");
  for (int u = 0; u < int(a.textures2d.size()); ++u)
    check(a.textures2d[u] == b.textures2d[u], "host 2D texture on unit " + std::to_string(u) + " kept");
  check(a.depthTest == b.depthTest && a.blend == b.blend && a.cullFace == b.cullFace &&
            a.scissorTest == b.scissorTest,
        "host depth test, blend, cull face and scissor switches kept");
  check(a.depthMask == b.depthMask && a.depthFunc == b.depthFunc, "host depth mask and function kept");
  check(a.blendSrc == b.blendSrc && a.blendDst == b.blendDst, "host blend function kept");
  check(a.packAlignment == b.packAlignment && a.unpackAlignment == b.unpackAlignment,
        "host pack/unpack alignment kept");
  check(a.clearColour == b.clearColour, "host clear colour kept");
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Baseline comparison: a per-channel tolerance, a bad-pixel fraction and a mean difference (the limits of
// dtfabric's own baseline tests).
bool compareBaseline(const dtf::Image& actual, const std::filesystem::path& baseline,
                     const std::filesystem::path& outDir) {
  if (envFlag("DTF_UPDATE_BASELINES")) {
    dtf::io::writePng(baseline.string(), actual);
    std::printf("updated baseline %s\n", baseline.c_str());
    return true;
  }
  if (!std::filesystem::exists(baseline)) {
    std::printf("no baseline %s (DTF_UPDATE_BASELINES=1 creates it)\n", baseline.c_str());
    return false;
  }
  const dtf::Image expected = dtf::io::readPng(baseline.string());
  if (expected.width != actual.width || expected.height != actual.height) {
    std::printf("baseline is %dx%d, the image %dx%d\n", expected.width, expected.height, actual.width, actual.height);
    return false;
  }
  dtf::Image diff(actual.width, actual.height);
  std::size_t bad = 0;
  double sum = 0;
  for (std::size_t i = 0; i < actual.rgba.size(); i += 4) {
    int worst = 0;
    for (int c = 0; c < 4; ++c) {
      const int d = std::abs(int(actual.rgba[i + c]) - int(expected.rgba[i + c]));
      worst = std::max(worst, d);
      sum += d;
      if (c < 3) diff.rgba[i + c] = static_cast<std::uint8_t>(std::min(255, d * 8));
    }
    diff.rgba[i + 3] = 255;
    bad += worst > 8;
  }
  const double pixels = double(actual.width) * actual.height;
  const double badFraction = bad / pixels, meanDiff = sum / (pixels * 4);
  std::printf("baseline: %.3f%% bad pixels, mean difference %.3f\n", 100 * badFraction, meanDiff);
  if (badFraction <= 0.01 && meanDiff <= 1.5) return true;
  dtf::io::writePng((outDir / "consumer_expected.png").string(), expected);
  dtf::io::writePng((outDir / "consumer_diff.png").string(), diff);
  return false;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: dtfabric_consumer SHARED_DATA_DIR BASELINE_PNG OUTPUT_DIR\n");
    return 1;
  }
  const std::filesystem::path dataDir = argv[1], baseline = argv[2], outDir = argv[3];
  std::filesystem::create_directories(outDir);
  std::printf("dtfabric %s\n", DTFABRIC_VERSION);

  // 1. The host's context.
  std::string why;
  if (!makeContext(why)) missing("DTF_REQUIRE_GL", why);
  std::printf("GL: %s / %s\n", glGetString(GL_RENDERER), glGetString(GL_VERSION));

  // 2. Real data through the public reader (values from the data's README, voxel (33, 42, 22) in the
  //    corpus callosum; the file is FSL-layout in the voxel frame of an LAS grid, so in world RAS the xy
  //    and xz components change sign).
  const std::filesystem::path tensorPath = dataDir / "iu_prisma_dwi/derived/dti_tensor.nii.gz";
  if (!std::filesystem::exists(tensorPath)) missing("DTF_REQUIRE_SHARED_DATA", "no " + tensorPath.string());
  auto t0 = std::chrono::steady_clock::now();
  const dtf::io::LoadedTensors loaded = dtf::io::readTensorVolume(tensorPath.string());
  std::printf("loaded %s in %.3f s\n", tensorPath.c_str(), seconds(t0));
  const dtf::TensorField& field = loaded.field;
  check(field.grid.dims == glm::ivec3(72, 72, 39), "dims 72x72x39");
  check(loaded.layout == dtf::io::TensorLayout::Fsl, "layout detected as fsl");
  check(field.grid.orientationCode() == "LAS", "grid orientation LAS");
  check(near(field.grid.spacing.x, 3.0, 1e-4) && near(field.grid.spacing.z, 3.0, 1e-4), "3 mm voxels");
  const dtf::SymTensor& cc = field.at(33, 42, 22);
  const std::array<double, 6> expected = {1.4692e-3, -1.1027e-4, 3.7012e-4, 2.0915e-4, -2.3325e-5, 3.4972e-4};
  const auto got = cc.components();
  bool same = field.valid[field.grid.index(33, 42, 22)] != 0;
  for (int c = 0; c < 6; ++c) same = same && near(got[c], expected[c], 1e-3 * std::abs(expected[c]) + 1e-9);
  check(same, "corpus callosum tensor in world RAS (xy, xz negated from the voxel frame)");
  check(near(dtf::fractionalAnisotropy(cc), 0.8463, 2e-3), "corpus callosum FA 0.8463");

  // 3. The host's geometry: a sphere from the public API whose top touches the corpus callosum voxel,
  //    drawn with raw GL and the host's own matrices (perspective, from above, anterior up: the patient's
  //    right on the image right).
  const double radius = 24.0, distance = 160.0, fovY = 30.0;
  const glm::dvec3 centre = field.grid.toWorld(glm::dvec3(33, 42, 22)) - glm::dvec3(0, 0, radius);
  const dtf::Mesh sphere = dtf::render::reference::uvSphere(centre, radius, 48, 96);
  const glm::dvec3 eye = centre + glm::dvec3(0, 0, distance), up(0, 1, 0);
  const glm::mat4 view = glm::lookAt(eye, centre, up);
  const glm::mat4 proj = glm::perspective(glm::radians(fovY), 1.0, 1.0, 1000.0);
  const glm::mat4 viewProj = proj * view;

  const HostTargets targets = makeTargets();
  const GLuint program = geometryProgram();
  GLuint vao = 0, buffers[3] = {};
  glGenVertexArrays(1, &vao);
  glGenBuffers(3, buffers);
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sphere.positions.size() * sizeof(glm::vec3)), sphere.positions.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, buffers[1]);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sphere.normals.size() * sizeof(glm::vec3)), sphere.normals.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[2]);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(sphere.indices.size() * sizeof(std::uint32_t)),
               sphere.indices.data(), GL_STATIC_DRAW);

  glBindFramebuffer(GL_FRAMEBUFFER, targets.fbo);
  glViewport(0, 0, kSize, kSize);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(program);
  glUniformMatrix4fv(glGetUniformLocation(program, "u_viewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
  glDrawElements(GL_TRIANGLES, GLsizei(sphere.indices.size()), GL_UNSIGNED_INT, nullptr);

  std::vector<float> hostDepth(kSize * kSize), hostNormal(kSize * kSize * 4);
  glReadPixels(0, 0, kSize, kSize, GL_DEPTH_COMPONENT, GL_FLOAT, hostDepth.data());
  glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, hostNormal.data());
  check(glGetError() == GL_NO_ERROR, "host geometry pass without GL errors");
  // Closed form: the sphere's outline subtends asin(r / d), so it covers pi R^2 pixels with
  // R = tan(asin(r / d)) / tan(fovY / 2) * size / 2.
  const double outline = std::tan(std::asin(radius / distance)) / std::tan(glm::radians(fovY) / 2) * kSize / 2;
  const double discPixels = glm::pi<double>() * outline * outline;
  const auto hostCovered = std::count_if(hostDepth.begin(), hostDepth.end(), [](float d) { return d < 1.0f; });
  std::printf("host sphere covers %td pixels (closed form %.0f)\n", hostCovered, discPixels);
  check(std::abs(hostCovered - discPixels) < 0.02 * discPixels, "host sphere covers its closed-form area");
  const float* n = &hostNormal[(kSize / 2 * kSize + kSize / 2) * 4];
  check(n[2] > 0.99f, "host normal at the image centre points up, towards the camera");

  // 4. Host state of its own, then the fabric through the public API on the same sphere and camera.
  GLuint unitTextures[2] = {};
  glGenTextures(2, unitTextures);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, targets.normal);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, targets.depth);
  glActiveTexture(GL_TEXTURE4);
  glBindTexture(GL_TEXTURE_2D, unitTextures[0]);
  glActiveTexture(GL_TEXTURE7);
  glBindTexture(GL_TEXTURE_2D, unitTextures[1]);
  glActiveTexture(GL_TEXTURE3);
  glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  glViewport(7, 9, 230, 220);
  glScissor(3, 4, 200, 190);
  glEnable(GL_SCISSOR_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_CULL_FACE);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glPixelStorei(GL_PACK_ALIGNMENT, 2);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glClearColor(0.1f, 0.2f, 0.3f, 0.4f);

  // The camera type of dtfabric's own front ends gives the same matrices as the host's glm calls.
  dtf::render::Camera camera;
  camera.lookAt(eye, centre, up);
  camera.orthographic = false;
  camera.fovYDeg = fovY;
  camera.nearPlane = 1.0;
  camera.farPlane = 1000.0;
  bool sameMatrices = true;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      sameMatrices = sameMatrices && near(camera.view()[c][r], view[c][r], 1e-4) &&
                     near(camera.projection(1.0)[c][r], proj[c][r], 1e-6);
  check(sameMatrices, "dtf::render::Camera gives the host's glm::lookAt/perspective matrices");

  // The host's output framebuffer: its own colour texture and depth buffer, cleared by the host. The
  // geometry pass's depth texture is input only (sampling an attached depth texture would be a feedback loop).
  GLuint outColour = 0, outDepth = 0, outFbo = 0;
  glGenTextures(1, &outColour);
  glActiveTexture(GL_TEXTURE5);
  glBindTexture(GL_TEXTURE_2D, outColour);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kSize, kSize, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindTexture(GL_TEXTURE_2D, 0);
  glActiveTexture(GL_TEXTURE3);
  glGenRenderbuffers(1, &outDepth);
  glBindRenderbuffer(GL_RENDERBUFFER, outDepth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, kSize, kSize);
  glGenFramebuffers(1, &outFbo);
  glBindFramebuffer(GL_FRAMEBUFFER, outFbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, outColour, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, outDepth);
  check(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE, "host output framebuffer complete");
  {
    // The host clears with its own state switched off for the clear, then puts it back.
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glDepthMask(GL_FALSE);
    glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
  }
  const HostState before = HostState::capture();

  t0 = std::chrono::steady_clock::now();
  dtf::Image image(kSize, kSize);
  {
    dtf::render::EmbeddedFabric fabric;
    fabric.setField(field);
    checkStateKept(before, HostState::capture());
    dtf::render::HostView hv;
    hv.depthTexture = targets.depth;
    hv.normalTexture = targets.normal;
    hv.normalEncoding = dtf::render::NormalEncoding::Signed;
    hv.view = view;
    hv.projection = proj;
    hv.viewport = {0, 0, kSize, kSize};
    hv.framebuffer = outFbo;
    dtf::render::FabricParams params;
    params.background = glm::vec3(0.0f);
    params.look = dtf::render::Look::Plain; // the paper's look, as consumer_sphere.png holds it
    fabric.drawStill(hv, params);
    std::printf("fabric drawn into the host's framebuffer in %.3f s (%d advection iterations)\n", seconds(t0),
                fabric.lastIterations());
    checkStateKept(before, HostState::capture());
    fabric.draw(hv, params); // an interactive frame after the still: the state is kept there too
    checkStateKept(before, HostState::capture());
  }
  checkStateKept(before, HostState::capture()); // and after the destructor

  // Read the host's framebuffer back: colour (rows bottom-up) and the depth the fabric wrote.
  std::vector<std::uint8_t> rgba(std::size_t(kSize) * kSize * 4);
  std::vector<float> fabricDepth(std::size_t(kSize) * kSize);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, outFbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glReadPixels(0, 0, kSize, kSize, GL_DEPTH_COMPONENT, GL_FLOAT, fabricDepth.data());
  for (int y = 0; y < kSize; ++y)
    std::copy_n(&rgba[std::size_t(kSize - 1 - y) * kSize * 4], kSize * 4, image.pixel(0, y));
  std::size_t agree = 0, both = 0;
  double worst = 0;
  for (int i = 0; i < kSize * kSize; ++i) {
    const bool h = hostDepth[i] < 1.0f, f = fabricDepth[i] < 1.0f;
    agree += h == f;
    if (h && f) {
      ++both;
      worst = std::max(worst, double(std::abs(hostDepth[i] - fabricDepth[i])));
    }
  }
  std::printf("coverage agreement %.4f, largest depth difference %.2e over %zu pixels\n",
              double(agree) / (kSize * kSize), worst, both);
  check(agree >= 0.995 * kSize * kSize, "the fabric covers the pixels the host's sphere covers");
  check(worst < 1e-3, "the depth the fabric wrote equals the host's");
  check(glGetError() == GL_NO_ERROR, "no GL errors");

  // 5. The image: the corpus callosum red at the top of the sphere (the image centre), the background
  //    where the host's sphere is not, and the same as the baseline.
  dtf::io::writePng((outDir / "consumer_actual.png").string(), image);
  check(image.width == kSize && image.height == kSize, "image 256x256");
  glm::dvec3 mean(0.0);
  for (int y = kSize / 2 - 8; y < kSize / 2 + 8; ++y)
    for (int x = kSize / 2 - 8; x < kSize / 2 + 8; ++x)
      mean += glm::dvec3(image.pixel(x, y)[0], image.pixel(x, y)[1], image.pixel(x, y)[2]) / 256.0;
  std::printf("mean colour at the image centre (%.1f, %.1f, %.1f)\n", mean.x, mean.y, mean.z);
  check(mean.x > 1.5 * mean.y && mean.x > 1.5 * mean.z, "corpus callosum red (left-right) at the image centre");
  std::size_t backgroundKept = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      // Image row 0 is the top; the host's depth rows start at the bottom.
      if (hostDepth[std::size_t(kSize - 1 - y) * kSize + x] >= 1.0f) backgroundKept += p[0] + p[1] + p[2] == 0;
    }
  check(backgroundKept == std::size_t(kSize * kSize - hostCovered), "background wherever the host's sphere is not");
  check(compareBaseline(image, baseline, outDir), "image matches " + baseline.filename().string());

  std::printf("dtfabric_consumer: %s (%d failed checks)\n", gFailures ? "FAILED" : "PASSED", gFailures);
  return gFailures ? 1 : 0;
}
