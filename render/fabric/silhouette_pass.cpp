#include "render/fabric/silhouette_pass.h"

namespace dtf::render {

SilhouettePass::SilhouettePass()
    : program_("common/fullscreen.vert", "fabric/silhouette.frag"), vao_(createVertexArray()) {}

void SilhouettePass::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  edges_ = Texture::create2D(GL_R16F, target.x, target.y);
  edges_.setFilter(GL_NEAREST, GL_NEAREST);
  edges_.setWrap(GL_CLAMP_TO_BORDER); // outside the target counts as blocked for the advection
  const float one[4] = {1, 1, 1, 1};
  glTextureParameterfv(edges_.id(), GL_TEXTURE_BORDER_COLOR, one);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&edges_}, nullptr);
}

void SilhouettePass::run(const Texture& surface, float thresholdMm, float backgroundMm) {
  resize({surface.width(), surface.height()});
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  program_.set("u_threshold", thresholdMm);
  program_.set("u_background", backgroundMm);
  program_.use();
  glBindTextureUnit(0, surface.id());
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

void SilhouettePass::clear() {
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero);
}

} // namespace dtf::render
