#include "render/fabric/geometry_stage.h"

namespace dtf::render {

GeometryStage::GeometryStage()
    : meshProgram_("fabric/geometry.vert", "fabric/geometry.frag"),
      importProgram_("common/deferred.vert", "fabric/host_import.frag"), vao_(createVertexArray()) {
  glCreateSamplers(1, &sampler_);
  glSamplerParameteri(sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

GeometryStage::~GeometryStage() {
  if (sampler_) glDeleteSamplers(1, &sampler_);
}

void GeometryStage::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  geometry_ = Texture::create2D(GL_RG32UI, target.x, target.y);
  depth_ = Texture::create2D(GL_DEPTH_COMPONENT32F, target.x, target.y);
  geometry_.setFilter(GL_NEAREST, GL_NEAREST);
  depth_.setFilter(GL_NEAREST, GL_NEAREST);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&geometry_}, &depth_);
}

void GeometryStage::clear() {
  const GLuint none[4] = {0, 0, 0, 0};
  const float one = 1.0f;
  glClearNamedFramebufferuiv(fbo_.id(), GL_COLOR, 0, none);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
}

void GeometryStage::run(const GpuMesh& mesh, const FrameView& view, bool cullHidden, bool draw) {
  resize(view.target);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  clear();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  meshProgram_.set("u_viewProj", view.viewProj);
  meshProgram_.set("u_view", view.view);
  meshProgram_.use();
  if (draw) mesh.drawVisible(cullHidden);
  glDisable(GL_DEPTH_TEST);
}

void GeometryStage::import(const HostSurface& host, const FrameView& view) {
  resize(view.target);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  glDisable(GL_BLEND);
  clear();
  // Every fragment writes its depth (gl_FragDepth); GL_ALWAYS keeps the test from reading the cleared one.
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  const ShaderProgram& p = importProgram_;
  p.set("u_clipToEye", view.clipToEye);
  p.set("u_hostClipToEye", glm::inverse(host.projection));
  p.set("u_projection", host.projection);
  p.set("u_viewRot", view.viewRot);
  p.set("u_biasedNormals", host.biasedNormals ? 1 : 0);
  glProgramUniform2i(p.id(), p.location("u_origin"), host.origin.x, host.origin.y);
  glProgramUniform2i(p.id(), p.location("u_extent"), view.viewport.x, view.viewport.y);
  p.set("u_guard", view.guard);
  p.use();
  glBindTextureUnit(0, host.depth);
  glBindTextureUnit(1, host.normal);
  glBindSampler(0, sampler_);
  glBindSampler(1, sampler_);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindSampler(0, 0);
  glBindSampler(1, 0);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
