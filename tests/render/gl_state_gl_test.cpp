// SPDX-License-Identifier: GPL-3.0-or-later
// The renderers leave the GL state as they found it: a host's framebuffer, viewport, switches, program,
// vertex array and texture bindings are the same after a fabric frame, a still, a Phong frame, a tract draw
// and a tract layer frame as before them.
#include "render/fabric_renderer.h"
#include "render/gl_objects.h"
#include "render/gl_state.h"
#include "render/reference/scenes.h"
#include "render/tract_layer.h"
#include "render/tract_renderer.h"
#include "io/model/fibre_set.h"
#include "support/gl_test.h"

using namespace dtf;
using namespace dtf::render;

namespace {

class GlStateTest : public GlTest {};

std::string describe(const GlState& s) {
  std::string t = "draw fbo " + std::to_string(s.drawFramebuffer) + ", read fbo " +
                  std::to_string(s.readFramebuffer) + ", viewport " + std::to_string(s.viewport[0]) + " " +
                  std::to_string(s.viewport[1]) + " " + std::to_string(s.viewport[2]) + " " +
                  std::to_string(s.viewport[3]) + ", depth " + std::to_string(s.depthTest) + ", blend " +
                  std::to_string(s.blend) + ", cull " + std::to_string(s.cullFace) + ", scissor " +
                  std::to_string(s.scissorTest) + ", depth mask " + std::to_string(s.depthMask) +
                  ", depth func " + std::to_string(s.depthFunc) + ", program " + std::to_string(s.program) +
                  ", vao " + std::to_string(s.vertexArray) + ", active texture " +
                  std::to_string(s.activeTexture - GL_TEXTURE0) + ", textures";
  for (GLint id : s.textures2d)
    t += " " + std::to_string(id);
  return t;
}

} // namespace

TEST_F(GlStateTest, FramesLeaveTheHostStateAsTheyFoundIt) {
  FabricRenderer fabric;
  fabric.setMesh(reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8));
  fabric.setField(reference::constantField(reference::centredGrid(32, 2.0), {0, 1, 0}));
  fabric.resize(96, 96);
  const Camera camera = Camera::standard(StandardView::Superior, {-30, -30, -30}, {30, 30, 30}, 1.0);
  Polylines lines;
  lines.offsets = {0};
  for (int k = 0; k <= 50; ++k)
    lines.points.emplace_back(float(k) - 25.0f, 0.0f, 1.0f);
  lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  TractRenderer tracts;
  tracts.setTracts(lines);
  TractLayer layer;

  // A host's state, nothing like GL's defaults: its own framebuffer, a viewport, every switch on, a vertex
  // array, textures on units 0, 3 and 7 and unit 3 active, images on units 0 and 4 (which the passes use).
  Texture hostTexture = Texture::create2D(GL_RGBA8, 8, 8);
  Texture hostColour = Texture::create2D(GL_RGBA8, 32, 32);
  Framebuffer hostFbo = createFramebuffer();
  attachTargets(hostFbo, {&hostColour}, nullptr);
  VertexArray hostVao = createVertexArray();
  glBindFramebuffer(GL_FRAMEBUFFER, hostFbo.id());
  glViewport(3, 4, 20, 21);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glEnable(GL_CULL_FACE);
  glEnable(GL_SCISSOR_TEST);
  glScissor(5, 6, 7, 8);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_GREATER);
  glBindVertexArray(hostVao.id());
  for (int unit : {0, 3, 7}) {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, hostTexture.id());
  }
  glActiveTexture(GL_TEXTURE3);
  glPixelStorei(GL_PACK_ALIGNMENT, 8);
  glBindImageTexture(0, hostTexture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  glBindImageTexture(4, hostTexture.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  const GlState before = GlState::capture();
  ASSERT_EQ(before.images[4], (std::array<GLint, 6>{static_cast<GLint>(hostTexture.id()), 0, GL_FALSE, 0,
                                                     GL_READ_WRITE, GL_R32UI}));
  ASSERT_EQ(before.drawFramebuffer, static_cast<GLint>(hostFbo.id()));
  ASSERT_EQ(before.textures2d[7], static_cast<GLint>(hostTexture.id()));
  ASSERT_EQ(before.scissorBoxes[0], (std::array<GLint, 4>{5, 6, 7, 8}));

  FabricParams p;
  p.stillMaxIterations = 5;
  fabric.renderFrame(camera, p);
  EXPECT_EQ(GlState::capture(), before) << "after renderFrame: " << describe(GlState::capture());
  const Image still = fabric.renderStill(camera, p);
  EXPECT_EQ(GlState::capture(), before) << "after renderStill: " << describe(GlState::capture());
  fabric.renderPhong(camera, {0.8f, 0.8f, 0.8f});
  EXPECT_EQ(GlState::capture(), before) << "after renderPhong: " << describe(GlState::capture());
  tracts.draw(fabric.frameView(), TractStyle{});
  EXPECT_EQ(GlState::capture(), before) << "after a tract draw: " << describe(GlState::capture());
  fabric.renderFrame(camera, p);
  TractLayer::Frame f;
  f.fabric = &fabric.output();
  f.fabricChanged = true;
  f.view = fabric.frameView();
  f.key = 1;
  layer.frame(tracts, f);
  EXPECT_EQ(GlState::capture(), before) << "after a tract layer frame: " << describe(GlState::capture());
  EXPECT_GT(still.width, 0);

  // The host's state drew nothing into the renders: the still is the one of GL's default state.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glScissor(0, 0, 32, 32);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  for (GLuint unit : {0u, 4u}) glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8);
  EXPECT_EQ(fabric.renderStill(camera, p).rgba, still.rgba);
}

// A host may delete its current program (GL keeps it until it is no longer in use). The first pass's
// glUseProgram then deletes it for good, so restoring its name would be GL_INVALID_VALUE (or, where the
// driver reuses freed names, bind whatever program took the name). The frame leaves no program current
// instead, and no GL error behind for the next upload to report.
TEST_F(GlStateTest, AHostProgramDeletedWhileCurrentIsNotRestored) {
  FabricRenderer fabric;
  const Grid grid = reference::centredGrid(16, 4.0);
  fabric.setMesh(reference::planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 60, 60, 8));
  fabric.setField(reference::constantField(grid, {0, 1, 0}));
  FibreSet fibres = makeFibreSet(grid, 3);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
    fibres.fibres[v * 3 + 0] = {glm::vec3(1, 0, 0), 1.0f};
    fibres.fibres[v * 3 + 1] = {glm::vec3(0, 1, 0), 0.7f};
    fibres.fibres[v * 3 + 2] = {glm::vec3(0, 0, 1), 0.5f};
  }
  fabric.setFibres(fibres);
  fabric.resize(64, 64);
  const Camera camera = Camera::standard(StandardView::Superior, {-30, -30, -30}, {30, 30, 30}, 1.0);
  FabricParams p;
  p.colour = ColourMode::Fibres;
  fabric.renderFrame(camera, p); // programs and targets exist before the host's program is made

  const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n";
  const char* fs = "#version 450 core\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n";
  auto hostProgram = [&] {
    GLuint program = glCreateProgram();
    for (auto [stage, src] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
      GLuint sh = glCreateShader(stage);
      glShaderSource(sh, 1, &src, nullptr);
      glCompileShader(sh);
      glAttachShader(program, sh);
      glDeleteShader(sh);
    }
    glLinkProgram(program);
    glUseProgram(program);
    glDeleteProgram(program); // flagged for deletion, still current
    return program;
  };
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

  for (ColourMode mode : {ColourMode::Fibres, ColourMode::Medical}) {
    const GLuint program = hostProgram();
    GLint current = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    ASSERT_EQ(current, static_cast<GLint>(program));
    p.colour = mode;
    fabric.renderFrame(camera, p);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "after a frame over a deleted host program";
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    EXPECT_EQ(current, 0);
    // The background upload checks for GL errors: none is left behind.
    const ScalarVolume fa(grid, 1, 0.5f);
    EXPECT_NO_THROW(fabric.setBackground(&fa));
    fabric.setBackground(nullptr);
  }
  // The same through renderPhong and readback.
  hostProgram();
  fabric.renderPhong(camera);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "after a Phong frame over a deleted host program";
  hostProgram();
  EXPECT_GT(fabric.readback().width, 0);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "after a readback over a deleted host program";
}
