// SPDX-License-Identifier: GPL-3.0-or-later
// The embedding API (render/embedding.h) as a host uses it: the host draws a sphere's depth and world
// normals with its own raw GL program into its own textures, then EmbeddedFabric draws the fabric into a
// viewport offset inside the host's larger framebuffer. Checked: the image agrees with FabricRenderer's
// still of the same sphere and camera, pixels outside the viewport keep the host's colour, the host's GL
// state (queried here with raw GL, independently of render/gl_state.h) is unchanged after every call and
// does not change the image, and the noise is anchored to the data (two meshes cut from the same field carry
// the same noise at the same world point).
#include "io/formats/png_io.h"
#include "render/embedding.h"
#include "render/fabric/projection_pass.h"
#include "render/fabric_renderer.h"
#include "render/gpu_scene.h"
#include "render/reference/scenes.h"
#include "support/gl_test.h"
#include "support/vector_texels.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <glm/gtc/type_ptr.hpp>
#include <string>
#include <vector>

using namespace dtf;
using namespace dtf::render;

namespace {

class Embedding : public GlTest {};

constexpr int kSize = 256;                // the viewport, as FabricRenderer's output
constexpr int kHostW = 340, kHostH = 300; // the host's framebuffer around it
const glm::ivec4 kViewport{52, 28, kSize, kSize};
constexpr float kHostClear[4] = {51 / 255.0f, 77 / 255.0f, 102 / 255.0f, 1.0f}; // exact in 8 bits

GLuint compile(GLenum stage, const char* src) {
  GLuint s = glCreateShader(stage);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  EXPECT_TRUE(ok) << "host shader failed to compile";
  return s;
}

// A host application's own rendering: raw GL, its own program and buffers, a G-buffer framebuffer (world
// normals + depth) and a display framebuffer (colour + the same depth texture).
struct Host {
  GLuint program = 0, vao = 0, vbo[2] = {0, 0}, ibo = 0, depth = 0, normal = 0, colour = 0, gbuffer = 0,
         display = 0;
  GLsizei indexCount = 0;
  bool biased = false;

  Host(const Mesh& mesh, GLenum depthFormat, GLenum normalFormat, bool biasedNormals)
      : biased(biasedNormals) {
    const char* vs = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_viewProj;
out vec3 v_normal;
void main() { v_normal = a_normal; gl_Position = u_viewProj * vec4(a_position, 1.0); })";
    const char* fs = R"(#version 450 core
in vec3 v_normal;
uniform bool u_biased;
layout(location = 0) out vec4 o_normal;
void main() { vec3 n = normalize(v_normal); o_normal = vec4(u_biased ? 0.5 * n + 0.5 : n, 1.0); })";
    GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
    program = glCreateProgram();
    glAttachShader(program, v);
    glAttachShader(program, f);
    glLinkProgram(program);
    glDeleteShader(v);
    glDeleteShader(f);
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo[0]);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.positions.size() * sizeof(glm::vec3)),
                 mesh.positions.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, vbo[1]);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.normals.size() * sizeof(glm::vec3)),
                 mesh.normals.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(1);
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)), mesh.indices.data(),
                 GL_STATIC_DRAW);
    indexCount = static_cast<GLsizei>(mesh.indices.size());
    glBindVertexArray(0);
    auto texture = [](GLenum format) {
      GLuint t = 0;
      glGenTextures(1, &t);
      glBindTexture(GL_TEXTURE_2D, t);
      glTexStorage2D(GL_TEXTURE_2D, 1, format, kHostW, kHostH);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR); // the fabric must not care
      glBindTexture(GL_TEXTURE_2D, 0);
      return t;
    };
    depth = texture(depthFormat);
    normal = texture(normalFormat);
    colour = texture(GL_RGBA8);
    const GLenum depthAttachment = depthFormat == GL_DEPTH24_STENCIL8 || depthFormat == GL_DEPTH32F_STENCIL8
                                       ? GL_DEPTH_STENCIL_ATTACHMENT
                                       : GL_DEPTH_ATTACHMENT;
    glGenFramebuffers(1, &gbuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, gbuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, normal, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, depthAttachment, GL_TEXTURE_2D, depth, 0);
    EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
    glGenFramebuffers(1, &display);
    glBindFramebuffer(GL_FRAMEBUFFER, display);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, depthAttachment, GL_TEXTURE_2D, depth, 0);
    EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  ~Host() {
    glDeleteFramebuffers(1, &gbuffer);
    glDeleteFramebuffers(1, &display);
    GLuint t[3] = {depth, normal, colour};
    glDeleteTextures(3, t);
    glDeleteBuffers(2, vbo);
    glDeleteBuffers(1, &ibo);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(program);
  }
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  // The host's geometry pass (normals cleared to 0, depth to 1) into the viewport, then its display
  // framebuffer cleared to its colour (the depth stays: the fabric is depth-tested against it).
  void drawGeometry(const glm::mat4& view, const glm::mat4& projection) {
    glBindFramebuffer(GL_FRAMEBUFFER, gbuffer);
    glViewport(0, 0, kHostW, kHostH);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glViewport(kViewport.x, kViewport.y, kViewport.z, kViewport.w);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_viewProj"), 1, GL_FALSE,
                       glm::value_ptr(projection * view));
    glUniform1i(glGetUniformLocation(program, "u_biased"), biased ? 1 : 0);
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, display);
    glViewport(0, 0, kHostW, kHostH);
    glClearColor(kHostClear[0], kHostClear[1], kHostClear[2], kHostClear[3]);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  HostView hostView(const glm::mat4& view, const glm::mat4& projection) const {
    HostView v;
    v.depthTexture = depth;
    v.normalTexture = normal;
    v.normalEncoding = biased ? NormalEncoding::Biased : NormalEncoding::Signed;
    v.view = view;
    v.projection = projection;
    v.viewport = kViewport;
    v.framebuffer = display;
    return v;
  }

  // The normal texture as floats, GL row order.
  std::vector<float> readNormals() const {
    std::vector<float> v(static_cast<std::size_t>(kHostW) * kHostH * 4);
    glGetTextureImage(normal, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(v.size() * sizeof(float)), v.data());
    return v;
  }

  // The whole colour texture, row 0 at the top.
  Image readColour() const {
    std::vector<std::uint8_t> rows(static_cast<std::size_t>(kHostW) * kHostH * 4);
    GLint pack = 4;
    glGetIntegerv(GL_PACK_ALIGNMENT, &pack);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(colour, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rows.size()), rows.data());
    glPixelStorei(GL_PACK_ALIGNMENT, pack);
    Image img(kHostW, kHostH);
    const std::size_t stride = static_cast<std::size_t>(kHostW) * 4;
    for (int y = 0; y < kHostH; ++y)
      std::copy_n(&rows[static_cast<std::size_t>(kHostH - 1 - y) * stride], stride, &img.rgba[y * stride]);
    return img;
  }
};

// The viewport's part of a host image (row 0 at the top), as FabricRenderer's output would be.
Image viewportPart(const Image& host) {
  Image out(kSize, kSize);
  const int top = kHostH - (kViewport.y + kViewport.w);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      std::copy_n(host.pixel(kViewport.x + x, top + y), 4,
                  &out.rgba[(static_cast<std::size_t>(y) * kSize + x) * 4]);
  return out;
}

struct Sphere {
  Mesh mesh;
  TensorField field;
};

// The anisotropic Hessian field of |x|^2 + c xyz on a sphere of radius 40 mm (the bench's sphere, smaller).
Sphere sphere() {
  Sphere s;
  const double r = 40.0;
  s.mesh = reference::uvSphere({0, 0, 0}, r, 96, 96);
  s.mesh.computeNormals();
  s.field = reference::hessianField(
      reference::centredGrid(40, 2.0 * r * 1.1 / 39.0),
      [r](const glm::dvec3& p) { return reference::sphereFunction(p, r); }, 0.5);
  return s;
}

// Per-pixel comparison: fraction of pixels with a channel beyond `tolerance` and mean |difference|.
struct Diff {
  double badFraction = 0, mean = 0;
};
Diff compare(const Image& a, const Image& b, int tolerance, int x0 = 0, int y0 = 0, int x1 = kSize,
             int y1 = kSize) {
  Diff d;
  std::size_t bad = 0, n = 0;
  double sum = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      int worst = 0;
      for (int c = 0; c < 3; ++c) {
        int e = std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c]));
        worst = std::max(worst, e);
        sum += e;
      }
      bad += worst > tolerance;
      ++n;
    }
  d.badFraction = double(bad) / double(n);
  d.mean = sum / (3.0 * double(n));
  return d;
}

// The host's GL state, read with raw GL queries (independently of the renderers' own state guard): every
// piece of state a host may have set that a fabric frame could plausibly change.
struct Snapshot {
  std::vector<std::pair<std::string, std::vector<double>>> values;
  bool operator==(const Snapshot& o) const { return values == o.values; }
  std::string differences(const Snapshot& o) const {
    std::string out;
    for (std::size_t i = 0; i < values.size() && i < o.values.size(); ++i)
      if (values[i].second != o.values[i].second) {
        out += values[i].first + ":";
        for (double v : values[i].second)
          out += " " + std::to_string(v);
        out += " ->";
        for (double v : o.values[i].second)
          out += " " + std::to_string(v);
        out += "; ";
      }
    return out;
  }
};

Snapshot snapshot() {
  Snapshot s;
  auto ints = [&](const std::string& name, GLenum e, int n = 1) {
    std::vector<GLint> v(16, -12345);
    glGetIntegerv(e, v.data());
    s.values.push_back({name, std::vector<double>(v.begin(), v.begin() + n)});
  };
  auto floats = [&](const std::string& name, GLenum e, int n) {
    std::vector<GLfloat> v(16, -12345.0f);
    glGetFloatv(e, v.data());
    s.values.push_back({name, std::vector<double>(v.begin(), v.begin() + n)});
  };
  auto enabled = [&](const std::string& name, GLenum e) {
    s.values.push_back({name, {double(glIsEnabled(e))}});
  };
  ints("program", GL_CURRENT_PROGRAM);
  ints("vertex array", GL_VERTEX_ARRAY_BINDING);
  ints("array buffer", GL_ARRAY_BUFFER_BINDING);
  ints("draw framebuffer", GL_DRAW_FRAMEBUFFER_BINDING);
  ints("read framebuffer", GL_READ_FRAMEBUFFER_BINDING);
  ints("viewport", GL_VIEWPORT, 4);
  for (GLuint i = 1; i < 3; ++i) {
    GLfloat v[4];
    glGetFloati_v(GL_VIEWPORT, i, v);
    s.values.push_back({"viewport " + std::to_string(i), {v[0], v[1], v[2], v[3]}});
  }
  ints("scissor box", GL_SCISSOR_BOX, 4);
  enabled("scissor test", GL_SCISSOR_TEST);
  enabled("blend", GL_BLEND);
  for (GLuint i = 0; i < 4; ++i)
    s.values.push_back({"blend " + std::to_string(i), {double(glIsEnabledi(GL_BLEND, i))}});
  ints("blend src rgb", GL_BLEND_SRC_RGB);
  ints("blend dst alpha", GL_BLEND_DST_ALPHA);
  ints("blend equation", GL_BLEND_EQUATION_RGB);
  floats("blend colour", GL_BLEND_COLOR, 4);
  enabled("depth test", GL_DEPTH_TEST);
  ints("depth func", GL_DEPTH_FUNC);
  ints("depth mask", GL_DEPTH_WRITEMASK);
  floats("depth range", GL_DEPTH_RANGE, 2);
  ints("clip origin", GL_CLIP_ORIGIN);
  ints("clip depth mode", GL_CLIP_DEPTH_MODE);
  enabled("depth clamp", GL_DEPTH_CLAMP);
  enabled("cull face", GL_CULL_FACE);
  ints("cull face mode", GL_CULL_FACE_MODE);
  ints("front face", GL_FRONT_FACE);
  enabled("stencil test", GL_STENCIL_TEST);
  ints("stencil func", GL_STENCIL_FUNC);
  ints("stencil ref", GL_STENCIL_REF);
  ints("stencil pass op", GL_STENCIL_PASS_DEPTH_PASS);
  ints("stencil writemask", GL_STENCIL_WRITEMASK);
  ints("colour mask", GL_COLOR_WRITEMASK, 4);
  for (GLuint i = 1; i < 3; ++i) {
    GLboolean m[4];
    glGetBooleani_v(GL_COLOR_WRITEMASK, i, m);
    s.values.push_back(
        {"colour mask " + std::to_string(i), {double(m[0]), double(m[1]), double(m[2]), double(m[3])}});
  }
  floats("clear colour", GL_COLOR_CLEAR_VALUE, 4);
  floats("clear depth", GL_DEPTH_CLEAR_VALUE, 1);
  ints("clear stencil", GL_STENCIL_CLEAR_VALUE);
  ints("polygon mode", GL_POLYGON_MODE, 1);
  enabled("polygon offset fill", GL_POLYGON_OFFSET_FILL);
  floats("polygon offset factor", GL_POLYGON_OFFSET_FACTOR, 1);
  enabled("rasterizer discard", GL_RASTERIZER_DISCARD);
  enabled("colour logic op", GL_COLOR_LOGIC_OP);
  enabled("framebuffer sRGB", GL_FRAMEBUFFER_SRGB);
  enabled("clip distance 0", GL_CLIP_DISTANCE0);
  floats("line width", GL_LINE_WIDTH, 1);
  ints("pack alignment", GL_PACK_ALIGNMENT);
  ints("unpack alignment", GL_UNPACK_ALIGNMENT);
  ints("pack row length", GL_PACK_ROW_LENGTH);
  ints("unpack row length", GL_UNPACK_ROW_LENGTH);
  ints("unpack skip rows", GL_UNPACK_SKIP_ROWS);
  ints("pixel pack buffer", GL_PIXEL_PACK_BUFFER_BINDING);
  ints("pixel unpack buffer", GL_PIXEL_UNPACK_BUFFER_BINDING);
  ints("uniform buffer", GL_UNIFORM_BUFFER_BINDING);
  ints("atomic counter buffer", GL_ATOMIC_COUNTER_BUFFER_BINDING);
  {
    GLint b = -1;
    glGetIntegeri_v(GL_ATOMIC_COUNTER_BUFFER_BINDING, 0, &b);
    s.values.push_back({"atomic counter buffer 0", {double(b)}});
  }
  ints("active texture", GL_ACTIVE_TEXTURE);
  GLint active = GL_TEXTURE0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (int u = 0; u < 10; ++u) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
    GLint t2 = -1, t3 = -1, smp = -1;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &t2);
    glGetIntegerv(GL_TEXTURE_BINDING_3D, &t3);
    glGetIntegerv(GL_SAMPLER_BINDING, &smp);
    s.values.push_back(
        {"unit " + std::to_string(u) + " 2D, 3D, sampler", {double(t2), double(t3), double(smp)}});
  }
  glActiveTexture(static_cast<GLenum>(active));
  return s;
}

// A host's state far from GL's defaults, on every switch the fabric's passes depend on.
struct HostState {
  GLuint vao = 0, buffer = 0, sampler = 0, tex2d = 0, tex3d = 0;
  HostState() {
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, 4096, nullptr, GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glGenSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_MIRRORED_REPEAT);
    glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glGenTextures(1, &tex2d);
    glBindTexture(GL_TEXTURE_2D, tex2d);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 4, 4);
    glGenTextures(1, &tex3d);
    glBindTexture(GL_TEXTURE_3D, tex3d);
    glTexStorage3D(GL_TEXTURE_3D, 1, GL_R8, 2, 2, 2);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindTexture(GL_TEXTURE_3D, 0);
  }
  ~HostState() {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &buffer);
    glDeleteSamplers(1, &sampler);
    glDeleteTextures(1, &tex2d);
    glDeleteTextures(1, &tex3d);
  }
  HostState(const HostState&) = delete;
  HostState& operator=(const HostState&) = delete;

  void apply(GLuint readFbo, GLuint drawFbo, GLuint program) const {
    glUseProgram(program);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, drawFbo);
    glViewport(5, 6, 70, 80);
    glViewportIndexedf(2, 1, 2, 30, 40);
    glScissor(3, 4, 50, 60);
    glEnable(GL_SCISSOR_TEST);
    glEnable(GL_BLEND);
    glDisablei(GL_BLEND, 1);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO);
    glBlendEquation(GL_FUNC_SUBTRACT);
    glBlendColor(0.1f, 0.2f, 0.3f, 0.4f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GEQUAL);
    glDepthMask(GL_FALSE);
    glDepthRange(0.2, 0.7);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_CLAMP);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    glFrontFace(GL_CW);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, 3, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
    glStencilMask(0x0f);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
    glColorMaski(2, GL_FALSE, GL_TRUE, GL_FALSE, GL_TRUE);
    glClearColor(0.9f, 0.8f, 0.7f, 0.6f);
    glClearDepth(0.25);
    glClearStencil(7);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.0f, 1.0f);
    glEnable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_XOR);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_CLIP_DISTANCE0);
    glLineWidth(1.0f);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
    glPixelStorei(GL_PACK_ROW_LENGTH, 17);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 13);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 2);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
    glBindBuffer(GL_UNIFORM_BUFFER, buffer);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, buffer);
    for (int u = 0; u < 10; ++u) {
      glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
      glBindTexture(GL_TEXTURE_2D, tex2d);
      if (u % 2 == 0) glBindTexture(GL_TEXTURE_3D, tex3d);
      glBindSampler(static_cast<GLuint>(u), sampler);
    }
    glActiveTexture(GL_TEXTURE5);
  }

  // Back to GL's defaults.
  static void reset() {
    glUseProgram(0);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glBlendFuncSeparate(GL_ONE, GL_ZERO, GL_ONE, GL_ZERO);
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDepthRange(0.0, 1.0);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDisable(GL_DEPTH_CLAMP);
    glDisable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_STENCIL_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_COLOR_LOGIC_OP);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_CLIP_DISTANCE0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, 0);
    for (int u = 0; u < 10; ++u) {
      glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
      glBindTexture(GL_TEXTURE_2D, 0);
      glBindTexture(GL_TEXTURE_3D, 0);
      glBindSampler(static_cast<GLuint>(u), 0);
    }
    glActiveTexture(GL_TEXTURE0);
  }
};

Camera sphereCamera(bool orthographic) {
  Camera cam =
      Camera::standard(StandardView::Anterior, {-40, -40, -40}, {40, 40, 40}, 1.0, false, orthographic);
  cam.trackball({0, 0}, {0.25, 0.3});
  return cam;
}

void writeDebug(const std::string& name, const Image& img) {
  io::writePng((dtf::test::binaryDir() / (name + ".png")).string(), img);
}

} // namespace

// The fabric drawn by a host agrees with FabricRenderer's still of the same sphere and camera; the host's
// pixels outside the viewport (and inside it off the sphere) keep its colour.
TEST_F(Embedding, HostDrawAgreesWithTheRendererAndKeepsTheHostsPixels) {
  const Sphere s = sphere();
  for (bool orthographic : {true, false}) {
    SCOPED_TRACE(orthographic ? "orthographic" : "perspective");
    for (int zoom = 0; zoom < 2; ++zoom) { // 1: zoomed in, the sphere is cut by the viewport's edges
      SCOPED_TRACE(zoom ? "cut by the viewport's edges" : "whole sphere");
      Camera cam = sphereCamera(orthographic);
      if (zoom) cam.zoom(0.6);
      FabricParams p;
      p.colour = ColourMode::Medical;
      FabricRenderer own;
      own.setMesh(s.mesh);
      own.setField(s.field);
      own.resize(kSize, kSize);
      const Image expected = own.renderStill(cam, p);

      Host host(s.mesh, GL_DEPTH24_STENCIL8, GL_RGBA32F, false);
      const glm::mat4 view(cam.view()), projection(cam.projection(1.0));
      host.drawGeometry(view, projection);
      EmbeddedFabric fabric;
      fabric.setField(s.field);
      fabric.drawStill(host.hostView(view, projection), p);
      const Image all = host.readColour();
      const Image actual = viewportPart(all);
      const std::string tag = std::string(orthographic ? "ortho" : "persp") + (zoom ? "_cut" : "");

      // Outside the viewport: the host's clear colour, exactly.
      const int top = kHostH - (kViewport.y + kViewport.w);
      std::size_t outside = 0, changed = 0;
      for (int y = 0; y < kHostH; ++y)
        for (int x = 0; x < kHostW; ++x) {
          if (x >= kViewport.x && x < kViewport.x + kSize && y >= top && y < top + kSize) continue;
          ++outside;
          const auto* px = all.pixel(x, y);
          for (int c = 0; c < 4; ++c)
            changed += px[c] != static_cast<std::uint8_t>(std::lround(kHostClear[c] * 255));
        }
      EXPECT_GT(outside, 0u);
      EXPECT_EQ(changed, 0u) << "host pixels outside the viewport changed";

      // Inside: where the host drew no surface, the host's colour; elsewhere the same fabric. The two routes
      // differ by round-off (the host's depth read back from a 24-bit buffer, its normals from its own
      // pass: relative depth 5e-5, normals 1e-4, see ImportedGeometryBuffersMatchTheMeshStage), which can
      // move single pixels across a face switch of the noise (Eq. 9) or a silhouette threshold; and, when
      // the surface is cut by the viewport's edge, by the guard border: the renderer sees the real surface
      // there, the host route its tangent-plane continuation, which changes the threads within a few
      // pixels of the edge a little. Hence a strict bound inside a 16-pixel margin and a looser one overall.
      std::size_t hostBackground = 0, background = 0;
      const std::vector<float> normals = host.readNormals(); // alpha 0: the host drew no surface there
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const std::size_t hostRow = static_cast<std::size_t>(kViewport.y + kSize - 1 - y);
          if (normals[(hostRow * kHostW + static_cast<std::size_t>(kViewport.x + x)) * 4 + 3] != 0.0f)
            continue;
          ++background;
          const auto* a = actual.pixel(x, y);
          hostBackground += a[0] == 51 && a[1] == 77 && a[2] == 102;
        }
      if (zoom == 0) {
        EXPECT_GT(background, 10000u);
      }
      EXPECT_EQ(hostBackground, background) << "off the sphere the host's colour stays";
      // Compare the fabric where the renderer drew it (background pixels compared above).
      Image a = actual, e = expected;
      for (std::size_t i = 0; i < e.rgba.size(); i += 4)
        if (!(e.rgba[i] | e.rgba[i + 1] | e.rgba[i + 2])) std::fill_n(&a.rgba[i], 3, 0);
      const Diff all256 = compare(a, e, 24);
      const Diff inner = compare(a, e, 24, 16, 16, kSize - 16, kSize - 16);
      EXPECT_LT(inner.badFraction, 0.001);
      EXPECT_LT(inner.mean, 0.1);
      EXPECT_LT(all256.badFraction, 0.005);
      EXPECT_LT(all256.mean, 0.25);
      if (HasFailure()) { // for a look: build/embedding_*.png
        std::printf("%s: bad %.4f mean %.3f; inner bad %.4f mean %.3f\n", tag.c_str(), all256.badFraction,
                    all256.mean, inner.badFraction, inner.mean);
        writeDebug("embedding_" + tag + "_host", all);
        writeDebug("embedding_" + tag + "_renderer", expected);
      }
    }
  }
}

// Normals in an unsigned normalised texture (0.5 n + 0.5) and a 32-bit float depth texture give the same
// fabric as float normals (within the 8-bit normal's quantisation).
TEST_F(Embedding, BiasedUnsignedNormalsAndFloatDepthAreAccepted) {
  const Sphere s = sphere();
  const Camera cam = sphereCamera(false);
  const glm::mat4 view(cam.view()), projection(cam.projection(1.0));
  FabricParams p;
  Host reference(s.mesh, GL_DEPTH_COMPONENT32F, GL_RGBA32F, false);
  Host biased(s.mesh, GL_DEPTH_COMPONENT32F, GL_RGBA16, true);
  EmbeddedFabric fabric;
  fabric.setField(s.field);
  reference.drawGeometry(view, projection);
  fabric.drawStill(reference.hostView(view, projection), p);
  biased.drawGeometry(view, projection);
  fabric.drawStill(biased.hostView(view, projection), p);
  const Diff d = compare(viewportPart(reference.readColour()), viewportPart(biased.readColour()), 24);
  EXPECT_LT(d.badFraction, 0.02);
  EXPECT_LT(d.mean, 1.5);
}

// Every piece of the host's GL state is the same after each EmbeddedFabric call, and the host's state
// does not change the image.
TEST_F(Embedding, HostGlStateIsUnchangedAndDoesNotChangeTheImage) {
  const Sphere s = sphere();
  const Camera cam = sphereCamera(false);
  const glm::mat4 view(cam.view()), projection(cam.projection(1.0));
  FabricParams p;
  p.stillMaxIterations = 20;

  // Plain state: the reference image.
  Host host(s.mesh, GL_DEPTH24_STENCIL8, GL_RGBA32F, false);
  host.drawGeometry(view, projection);
  HostState::reset();
  Image plain;
  {
    EmbeddedFabric fabric;
    fabric.setField(s.field);
    fabric.drawStill(host.hostView(view, projection), p);
    plain = host.readColour();
  }

  host.drawGeometry(view, projection);
  HostState state;
  state.apply(host.gbuffer, host.display, host.program);
  const Snapshot before = snapshot();
  {
    EmbeddedFabric fabric;
    EXPECT_EQ(snapshot(), before) << "after construction: " << before.differences(snapshot());
    fabric.setField(s.field);
    EXPECT_EQ(snapshot(), before) << "after setField: " << before.differences(snapshot());
    fabric.drawStill(host.hostView(view, projection), p);
    EXPECT_EQ(snapshot(), before) << "after drawStill: " << before.differences(snapshot());
    HostState::reset();
    const Image hostStateImage = host.readColour();
    EXPECT_EQ(hostStateImage.rgba, plain.rgba) << "the host's state changed the image";
    state.apply(host.gbuffer, host.display, host.program);
    fabric.setTiming(true);
    fabric.draw(host.hostView(view, projection), p);
    EXPECT_EQ(snapshot(), before) << "after draw: " << before.differences(snapshot());
    EXPECT_GT(fabric.lastTimes().projection, 0.0);
    EXPECT_EQ(snapshot(), before) << "after lastTimes: " << before.differences(snapshot());
  }
  EXPECT_EQ(snapshot(), before) << "after destruction: " << before.differences(snapshot());
  HostState::reset();
}

// Frames continue the advection like FabricRenderer::renderFrame: repeated frames converge to the still,
// and a change of the matrices restarts from the noise.
TEST_F(Embedding, FramesContinueTheAdvectionAndConvergeToTheStill) {
  const Sphere s = sphere();
  const Camera cam = sphereCamera(false);
  const glm::mat4 view(cam.view()), projection(cam.projection(1.0));
  FabricParams p;
  Host host(s.mesh, GL_DEPTH24_STENCIL8, GL_RGBA32F, false);
  host.drawGeometry(view, projection);
  EmbeddedFabric fabric, stillFabric;
  fabric.setField(s.field);
  stillFabric.setField(s.field);
  stillFabric.drawStill(host.hostView(view, projection), p);
  const Image still = host.readColour();
  const int iterations = stillFabric.lastIterations();
  EXPECT_GT(iterations, 10);
  Image first, last;
  for (int f = 0; f * p.iterations < iterations + 12; ++f) {
    host.drawGeometry(view, projection);
    fabric.draw(host.hostView(view, projection), p);
    if (f == 0) first = host.readColour();
    last = host.readColour();
  }
  const Diff firstDiff = compare(viewportPart(first), viewportPart(still), 24);
  const Diff lastDiff = compare(viewportPart(last), viewportPart(still), 24);
  EXPECT_GT(firstDiff.mean, 3.0 * lastDiff.mean) << "one frame of 3 iterations is not converged";
  EXPECT_LT(lastDiff.badFraction, 0.02);
  // A moved camera restarts: the first frame after it is as far from converged as the first frame was.
  Camera moved = cam;
  moved.trackball({0, 0}, {0.05, 0});
  const glm::mat4 view2(moved.view());
  host.drawGeometry(view2, projection);
  fabric.draw(host.hostView(view2, projection), p);
  const Image restarted = host.readColour();
  host.drawGeometry(view2, projection);
  stillFabric.drawStill(host.hostView(view2, projection), p);
  const Diff restartDiff = compare(viewportPart(restarted), viewportPart(host.readColour()), 24);
  EXPECT_GT(restartDiff.mean, 2.0 * lastDiff.mean);
}

// The noise is anchored to the data: a sphere and a horizontal plane through it, each rendered alone from
// the same field with the same camera (orthographic, from above), carry the same beta wherever both
// surfaces face up (the noise's xy face, Eq. 9), although the meshes' bounds differ; shifting the data's
// grid by a fraction of the noise scale changes beta there.
TEST_F(Embedding, NoiseIsAnchoredToTheDataNotToTheMesh) {
  const double r = 40.0;
  const Sphere s = sphere();
  const Mesh plane = reference::planeMesh({3.7, -2.1, 0.8 * r}, {1, 0, 0}, {0, 1, 0}, 53.0, 71.0, 20);
  const Camera cam = Camera::standard(StandardView::Superior, {-45, -45, -45}, {45, 45, 45}, 1.0);
  FabricParams p;
  // Fixed (mm), so the noise scale does not follow the pixel size, and large enough that both surfaces
  // sample the tile's level 0 (a texel covers more than a pixel even on the tilted sphere).
  p.lod = 160.0;
  auto beta = [&](const Mesh& mesh, const TensorField& field) {
    FabricRenderer r;
    r.setMesh(mesh);
    r.setField(field);
    r.resize(kSize, kSize);
    p.stillMaxIterations = 1;
    r.renderStill(cam, p);
    return dtf::test::readTexture(r.projection().surface(), 4);
  };
  const std::vector<float> onSphere = beta(s.mesh, s.field), onPlane = beta(plane, s.field);
  TensorField shifted = s.field;
  shifted.grid.voxelToWorld[3] += glm::dvec4(0.37 * p.lod, 0.29 * p.lod, 0.0, 0.0);
  const std::vector<float> shiftedPlane = beta(plane, shifted);
  const int target = kSize + 2 * p.guard;
  // Pixels within 0.55 r of the centre: the sphere's normal there is within 34 degrees of +z.
  const glm::mat4 viewProj = glm::mat4(cam.projection(1.0) * cam.view());
  std::size_t shared = 0, different = 0, moved = 0;
  double worst = 0;
  for (int y = 0; y < target; ++y)
    for (int x = 0; x < target; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * target + x) * 4;
      if (onSphere[i + 3] < 0.5f || onPlane[i + 3] < 0.5f) continue;
      // The pixel's world x, y (orthographic from above).
      const glm::vec2 ndc((x - p.guard + 0.5f) / kSize * 2.0f - 1.0f,
                          (y - p.guard + 0.5f) / kSize * 2.0f - 1.0f);
      const glm::vec4 w = glm::inverse(viewProj) * glm::vec4(ndc, 0.0f, 1.0f);
      if (glm::length(glm::vec2(w.x, w.y)) > 0.55 * r) continue;
      ++shared;
      const double d = std::abs(onSphere[i] - onPlane[i]);
      worst = std::max(worst, d);
      different += d > 0.02;
      moved += std::abs(onPlane[i] - shiftedPlane[i]) > 0.05;
    }
  ASSERT_GT(shared, 5000u);
  EXPECT_EQ(different, 0u) << "worst |beta difference| " << worst;
  EXPECT_GT(double(moved), 0.5 * double(shared)) << "beta does not follow the data's grid";
}

// The host import writes the same geometry buffers as the mesh route inside the viewport: the same coverage,
// per covered pixel the same linear depth (to 1e-4 relative; the host's is read back from a 24-bit buffer)
// and normal (to 1e-3), and the tensor stage makes the same beta, light and directions of them.
TEST_F(Embedding, ImportedGeometryBuffersMatchTheMeshStage) {
  const Sphere s = sphere();
  for (bool orthographic : {false, true})
    for (int zoom = 0; zoom < 2; ++zoom) {
      SCOPED_TRACE(std::string(orthographic ? "ortho" : "persp") + (zoom ? " cut" : ""));
      Camera cam = sphereCamera(orthographic);
      if (zoom) cam.zoom(0.6);
      const glm::mat4 view(cam.view()), projection(cam.projection(1.0));
      glm::dvec3 l, h;
      s.field.grid.worldBounds(l, h);
      const FrameView fv = FrameView::fromHost(view, projection, {kSize, kSize}, 16, glm::vec3(l),
                                               glm::vec3(h), glm::vec3(0.5 * (l + h)));
      const FrameView mv = FrameView::make(cam, {kSize, kSize}, 16, glm::vec3(-40), glm::vec3(40));
      GpuMesh gm;
      gm.upload(s.mesh);
      GeometryStage meshStage, importStage;
      meshStage.run(gm, mv, false);
      Host host(s.mesh, GL_DEPTH24_STENCIL8, GL_RGBA32F, false);
      host.drawGeometry(view, projection);
      HostSurface hs;
      hs.depth = host.depth;
      hs.normal = host.normal;
      hs.origin = {kViewport.x, kViewport.y};
      hs.projection = projection;
      importStage.import(hs, fv);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      auto read = [](const Texture& t) {
        std::vector<std::uint32_t> v(static_cast<std::size_t>(t.width()) * t.height() * 2);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glGetTextureImage(t.id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(v.size() * 4),
                          v.data());
        return v;
      };
      const auto a = read(meshStage.geometry()), b = read(importStage.geometry());
      std::size_t coverDiff = 0, depthDiff = 0, covered = 0;
      double worstDepth = 0, worstNormal = 0;
      const int t = kSize + 32;
      for (int y = 16; y < 16 + kSize; ++y)
        for (int x = 16; x < 16 + kSize; ++x) {
          const std::size_t i = (static_cast<std::size_t>(y) * t + x) * 2;
          const bool ca = a[i + 1] != 0, cb = b[i + 1] != 0;
          coverDiff += ca != cb;
          if (!ca || !cb) continue;
          ++covered;
          float da, db;
          std::memcpy(&da, &a[i + 1], 4);
          std::memcpy(&db, &b[i + 1], 4);
          worstDepth = std::max(worstDepth, double(std::abs(da - db) / da));
          if (a[i] != b[i]) {
            auto un = [](std::uint32_t v) {
              return glm::vec2(float(std::int16_t(v & 0xffff)), float(std::int16_t(v >> 16))) / 32767.0f;
            };
            glm::vec2 na = un(a[i]), nb = un(b[i]);
            worstNormal = std::max(worstNormal, double(glm::length(na - nb)));
          }
          depthDiff += std::abs(da - db) > 1e-4 * da;
        }
      EXPECT_LT(worstNormal, 1e-3);
      {
        GpuTensorField gf;
        gf.upload(s.field);
        NoiseOptions no;
        Texture noise = uploadNoise(*cachedReactionDiffusion(no));
        ProjectionSettings ps;
        glm::dvec3 l2, h2;
        s.field.grid.worldBounds(l2, h2);
        ps.noiseOrigin = glm::vec3(l2);
        ps.lod = 256 * mv.pixelMm;
        TensorStage t1, t2;
        t1.run(meshStage, gf, noise, mv, ps);
        t2.run(importStage, gf, noise, fv, ps);
        const auto sa = dtf::test::readTexture(t1.surface(), 4), sb = dtf::test::readTexture(t2.surface(), 4);
        double wb = 0, wl = 0;
        for (std::size_t i = 0; i < sa.size(); i += 4) {
          const int px = int(i / 4) % t, py = int(i / 4) / t;
          if (px < 16 || py < 16 || px >= 16 + kSize || py >= 16 + kSize) continue;
          if (sa[i + 3] < 0.5f || sb[i + 3] < 0.5f) continue;
          wb = std::max(wb, double(std::abs(sa[i] - sb[i])));
          wl = std::max(wl, double(std::abs(sa[i + 1] - sb[i + 1])));
        }
        {
          const auto va = dtf::test::readVectors(t1.vectors()), vb = dtf::test::readVectors(t2.vectors());
          double wv = 0;
          std::size_t nz = 0;
          for (std::size_t i = 0; i < va.size(); i += 4) {
            const int px = int(i / 4) % t, py = int(i / 4) / t;
            if (px < 16 || py < 16 || px >= 16 + kSize || py >= 16 + kSize) continue;
            if (sa[i + 3] < 0.5f || sb[i + 3] < 0.5f) continue;
            for (int c = 0; c < 2; ++c) {
              const double d = glm::length(glm::vec2(va[i + 2 * c], va[i + 2 * c + 1]) -
                                           glm::vec2(vb[i + 2 * c], vb[i + 2 * c + 1]));
              wv = std::max(wv, d);
              nz += d > 0.05;
            }
          }
          EXPECT_LT(wv, 0.02) << nz << " directions differ by more than 0.05";
        }
        EXPECT_LT(wb, 0.01); // beta (the noise at a position reconstructed from depth; 0.0051 on an H100)
        EXPECT_LT(wl, 0.001); // light
        EXPECT_FLOAT_EQ(mv.pixelMm, fv.pixelMm);
      }
      // The two routes rasterise the same triangles with differently scaled viewport matrices (the mesh stage
      // into the guarded target): llvmpipe rounds them identically, a GPU (an H100) flips a few silhouette
      // pixels. Allowed: 0.2 % of the covered pixels.
      EXPECT_LE(coverDiff, covered / 500) << covered << " covered";
      EXPECT_LE(depthDiff, covered / 500) << "worst relative depth difference " << worstDepth;
    }
}

// An unusable view is refused with an error that names the problem, and the host's state survives it.
TEST_F(Embedding, BadViewsThrowAndLeaveTheStateAlone) {
  const Sphere s = sphere();
  Host host(s.mesh, GL_DEPTH_COMPONENT32F, GL_RGBA32F, false);
  const Camera cam = sphereCamera(false);
  EmbeddedFabric fabric;
  fabric.setField(s.field);
  HostState state;
  state.apply(host.gbuffer, host.display, host.program);
  const Snapshot before = snapshot();
  auto expectError = [&](HostView v, const std::string& words) {
    try {
      fabric.draw(v, FabricParams{});
      ADD_FAILURE() << "no error for " << words;
    } catch (const GlError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_EQ(snapshot(), before) << words << ": " << before.differences(snapshot());
  };
  const HostView good = host.hostView(glm::mat4(cam.view()), glm::mat4(cam.projection(1.0)));
  HostView v = good;
  v.depthTexture = 0;
  expectError(v, "the depth texture is not a texture");
  v = good;
  v.normalTexture = host.gbuffer + 1000;
  expectError(v, "the normal texture is not a texture");
  v = good;
  v.viewport.z = kHostW; // beyond the textures
  expectError(v, "the viewport needs");
  v = good;
  v.viewport.w = 0;
  expectError(v, "out of range");
  v = good;
  v.framebuffer = host.display + 1000; // no such framebuffer
  expectError(v, "is not a framebuffer");
  HostState::reset();
}
