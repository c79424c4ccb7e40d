#include "render/fabric/projection_pass.h"

namespace dtf::render {

ProjectionPass::ProjectionPass()
    : plain_("fabric/projection.vert", "fabric/projection.frag"),
      principal_("fabric/projection.vert", "fabric/projection.frag", {"WITH_PRINCIPAL"}),
      depthOnly_("fabric/projection.vert", "fabric/depth_only.frag"),
      samples_(createQuery(GL_SAMPLES_PASSED)) {}

void ProjectionPass::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  vectors_ = Texture::create2D(GL_RGBA16F, target.x, target.y);
  surface_ = Texture::create2D(GL_RGBA32F, target.x, target.y);
  eigen_ = Texture::create2D(GL_RGBA16F, target.x, target.y);
  lambda_ = Texture::create2D(GL_RGBA32F, target.x, target.y);
  depth_ = Texture::create2D(GL_DEPTH_COMPONENT32F, target.x, target.y);
  for (Texture* t : {&vectors_, &surface_, &eigen_, &lambda_, &depth_}) t->setFilter(GL_NEAREST, GL_NEAREST);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&vectors_, &surface_, &eigen_, &lambda_}, &depth_);
}

void ProjectionPass::run(const GpuMesh& mesh, const GpuTensorField& field, const Texture& noise,
                         const FrameView& view, const ProjectionSettings& s, const GpuScalarVolume* background) {
  resize(view.target);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < 4; ++i) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, i, zero);
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  const ShaderProgram& p = s.principal ? principal_ : plain_;
  p.set("u_viewProj", view.viewProj);
  p.set("u_view", view.view);
  p.set("u_viewRot", view.viewRot);
  p.set("u_targetSize", glm::vec2(size_));
  p.set("u_eps", 0.5f * view.pixelMm);
  p.set("u_degenerateTol", s.degenerateTol);
  p.set("u_orthographic", view.orthographic ? 1 : 0);
  p.set("u_pixelMm", view.pixelMm);
  p.set("u_pixelMmPerDepth", view.pixelMmPerDepth);
  p.set("u_noiseOrigin", s.noiseOrigin);
  p.set("u_lod", s.lod);
  p.set("u_noiseBlend", s.noiseBlend);
  p.set("u_worldToTex", field.worldToTex());
  p.set("u_faFloor", s.faFloor);
  const bool hasBackground = background && !background->empty();
  p.set("u_hasBackground", hasBackground ? 1 : 0);
  if (hasBackground) {
    p.set("u_backgroundWorldToTex", background->worldToTex());
    background->bind(3);
  }
  if (s.depthPrepass && !field.empty()) {
    depthOnly_.set("u_viewProj", view.viewProj);
    depthOnly_.set("u_view", view.view);
    depthOnly_.use();
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    mesh.draw();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
  }
  p.use();
  field.bind();
  glBindTextureUnit(2, noise.id());
  glBeginQuery(GL_SAMPLES_PASSED, samples_.id());
  if (!field.empty()) mesh.draw();
  glEndQuery(GL_SAMPLES_PASSED);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render

namespace dtf::render {
unsigned ProjectionPass::coveredPixels() const {
  GLuint n = 0;
  glGetQueryObjectuiv(samples_.id(), GL_QUERY_RESULT, &n);
  return n;
}
} // namespace dtf::render
