// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/geometry_stage.h"

namespace dtf::render {

GeometryStage::GeometryStage()
    : meshProgram_("fabric/geometry.vert", "fabric/geometry.frag", programDefines<GeometryProgram>(),
                   uniformNames<GeometryProgram::Uniform>()),
      importProgram_("fabric/host_import.vert", "fabric/host_import.frag",
                     programDefines<HostImportProgram>(), uniformNames<HostImportProgram::Uniform>()),
      vao_(createVertexArray()), sampler_(createTexelSampler()) {}

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
  meshProgram_.set(GeometryProgram::Uniform::ViewProj, view.viewProj);
  meshProgram_.set(GeometryProgram::Uniform::View, view.view);
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
  using U = HostImportProgram::Uniform;
  using Unit = HostImportProgram::Unit;
  const ShaderProgram& p = importProgram_;
  p.set(U::ClipToEye, view.clipToEye);
  p.set(U::HostClipToEye, glm::inverse(host.projection));
  p.set(U::Projection, host.projection);
  p.set(U::ViewRot, view.viewRot);
  p.set(U::BiasedNormals, host.biasedNormals ? 1 : 0);
  p.set(U::Origin, glm::ivec2(host.origin.x, host.origin.y));
  p.set(U::Extent, glm::ivec2(view.viewport.x, view.viewport.y));
  p.set(U::Guard, view.guard);
  p.use();
  bindTexture(Unit::HostDepth, host.depth);
  bindTexture(Unit::HostNormal, host.normal);
  glBindSampler(unit(Unit::HostDepth), sampler_.id());
  glBindSampler(unit(Unit::HostNormal), sampler_.id());
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindSampler(unit(Unit::HostDepth), 0);
  glBindSampler(unit(Unit::HostNormal), 0);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
