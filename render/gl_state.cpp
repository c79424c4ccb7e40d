#include "render/gl_state.h"

namespace dtf::render {

namespace {
void setSwitch(GLenum cap, GLboolean on) {
  if (on)
    glEnable(cap);
  else
    glDisable(cap);
}
} // namespace

GlState GlState::capture() {
  GlState s;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.drawFramebuffer);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s.readFramebuffer);
  glGetIntegerv(GL_VIEWPORT, s.viewport.data());
  s.depthTest = glIsEnabled(GL_DEPTH_TEST);
  s.blend = glIsEnabled(GL_BLEND);
  s.cullFace = glIsEnabled(GL_CULL_FACE);
  s.scissorTest = glIsEnabled(GL_SCISSOR_TEST);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depthMask);
  glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
  glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s.vertexArray);
  glGetIntegerv(GL_ATOMIC_COUNTER_BUFFER_BINDING, &s.atomicCounterBuffer);
  glGetIntegerv(GL_PACK_ALIGNMENT, &s.packAlignment);
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &s.unpackAlignment);
  glGetIntegerv(GL_ACTIVE_TEXTURE, &s.activeTexture);
  for (int u = 0; u < kTextureUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + u);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &s.textures2d[u]);
  }
  glActiveTexture(static_cast<GLenum>(s.activeTexture));
  return s;
}

void GlState::restore() const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(drawFramebuffer));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readFramebuffer));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  setSwitch(GL_DEPTH_TEST, depthTest);
  setSwitch(GL_BLEND, blend);
  setSwitch(GL_CULL_FACE, cullFace);
  setSwitch(GL_SCISSOR_TEST, scissorTest);
  glDepthMask(depthMask);
  glDepthFunc(static_cast<GLenum>(depthFunc));
  glUseProgram(static_cast<GLuint>(program));
  glBindVertexArray(static_cast<GLuint>(vertexArray));
  glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, static_cast<GLuint>(atomicCounterBuffer));
  glPixelStorei(GL_PACK_ALIGNMENT, packAlignment);
  glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
  for (int u = 0; u < kTextureUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + u);
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(textures2d[u]));
  }
  glActiveTexture(static_cast<GLenum>(activeTexture));
}

GlStateGuard::GlStateGuard() : saved_(GlState::capture()) {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

GlStateGuard::~GlStateGuard() {
  saved_.restore();
}

} // namespace dtf::render
