// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/silhouette_pass.h"

namespace dtf::render {

namespace {
using U = SilhouetteProgram::Uniform;

std::vector<std::string> silhouetteDefines(bool farPlane) {
  std::vector<std::string> d = programDefines<SilhouetteProgram>();
  if (farPlane) d.push_back("FAR_PLANE");
  return d;
}
} // namespace

SilhouettePass::SilhouettePass()
    : program_("fabric/silhouette.vert", "fabric/silhouette.frag", silhouetteDefines(false),
               uniformNames<U>()),
      covered_("fabric/silhouette.vert", "fabric/silhouette.frag", silhouetteDefines(true),
               uniformNames<U>()),
      vao_(createVertexArray()) {}

void SilhouettePass::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  edges_ = Texture::create2D(GL_R8, target.x, target.y);
  edges_.setFilter(GL_NEAREST, GL_NEAREST);
  edges_.setWrap(GL_CLAMP_TO_BORDER); // outside the target counts as blocked for the advection
  const float one[4] = {1, 1, 1, 1};
  glTextureParameterfv(edges_.id(), GL_TEXTURE_BORDER_COLOR, one);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&edges_}, nullptr);
  attachedDepth_ = 0;
}

void SilhouettePass::run(const Texture& surface, float thresholdMm, float backgroundMm,
                         const Texture* depth) {
  resize({surface.width(), surface.height()});
  const GLuint depthId = depth ? depth->id() : 0;
  if (depthId != attachedDepth_) {
    glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depthId, 0);
    attachedDepth_ = depthId;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  const ShaderProgram& p = depth ? covered_ : program_;
  p.set(U::Threshold, thresholdMm);
  p.set(U::Background, backgroundMm);
  p.use();
  bindTexture(SilhouetteProgram::Unit::Surface, surface.id());
  bindReadImage(SilhouetteProgram::Image::Surface, surface, GL_RGBA32F);
  glBindVertexArray(vao_.id());
  if (depth) {
    const float one[4] = {1, 1, 1, 1};
    glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
  }
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (depth) {
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
  }
}

void SilhouettePass::clear() {
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero);
}

} // namespace dtf::render
