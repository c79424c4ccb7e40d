#include "render/fabric/projection_pass.h"

namespace dtf::render {

namespace {
using Unit = ProjectionProgram::Unit;
using U = ProjectionProgram::Uniform;
} // namespace

TensorStage::TensorStage()
    : program_("common/deferred.vert", "fabric/projection.frag",
               {"WITH_PRINCIPAL", "NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY"}, programDefines<ProjectionProgram>(),
               uniformNames<U>()),
      vao_(createVertexArray()), samples_(createQuery(GL_SAMPLES_PASSED)) {
  program_.get(1); // the default variant compiles with the pass, so a broken shader fails early
}

void TensorStage::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  vectors_ = Texture::create2D(GL_RGBA32UI, target.x, target.y);
  surface_ = Texture::create2D(GL_RGBA32F, target.x, target.y);
  eigen_ = Texture::create2D(GL_RGBA8, target.x, target.y);
  lambda_ = Texture::create2D(GL_RGBA8, target.x, target.y);
  fibres_ = Texture::create2D(GL_RGBA32UI, target.x, target.y);
  for (Texture* t : {&vectors_, &surface_, &eigen_, &lambda_, &fibres_})
    t->setFilter(GL_NEAREST, GL_NEAREST);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&vectors_, &surface_, &eigen_, &lambda_}, nullptr);
  fibreFbo_ = createFramebuffer();
  attachTargets(fibreFbo_, {&vectors_, &surface_, &eigen_, &lambda_, &fibres_}, nullptr);
  attachedDepth_ = 0;
}

void TensorStage::attachDepth(const Texture& depth) {
  if (depth.id() == attachedDepth_) return;
  for (const Framebuffer* f : {&fbo_, &fibreFbo_})
    glNamedFramebufferTexture(f->id(), GL_DEPTH_ATTACHMENT, depth.id(), 0);
  attachedDepth_ = depth.id();
}

void TensorStage::run(const GeometryStage& geometry, const GpuTensorField& field, const Texture& noise,
                      const FrameView& view, const ProjectionSettings& s, const GpuScalarVolume* background,
                      const GpuFibreSet* fibres) {
  const bool useFibres = s.fibres && fibres && !fibres->empty();
  const bool haveData = s.fibres ? useFibres : !field.empty();
  resize(geometry.size());
  attachDepth(geometry.depth());
  const float zero[4] = {0, 0, 0, 0};
  glViewport(0, 0, size_.x, size_.y);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);

  // At the far plane: GL_GREATER passes exactly where the geometry stage found a surface.
  const Framebuffer& target = useFibres ? fibreFbo_ : fbo_;
  glBindFramebuffer(GL_FRAMEBUFFER, target.id());
  // Only the surface target is cleared (its .a is the coverage the later passes test); the others are
  // read where the surface is covered only, and clearing them costs as much as a fullscreen pass.
  glClearNamedFramebufferfv(target.id(), GL_COLOR, 1, zero);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_FALSE);
  const bool hasBackground = background && !background->empty();
  const bool fray = s.uncertainty && !s.uncertainty->empty() && s.fray > 0.0f;
  const ShaderProgram& p =
      program_.get((s.principal && !useFibres ? 1u : 0u) | (s.noiseBlend > 0.0f ? 2u : 0u) |
                   (hasBackground ? 4u : 0u) | (useFibres ? 8u : 0u) | (fray ? 16u : 0u));
  p.set(U::ClipToEye, view.clipToEye);
  p.set(U::EyeToWorld, view.eyeToWorld);
  p.set(U::ViewProj, view.viewProj);
  p.set(U::ViewRot, view.viewRot);
  p.set(U::TargetSize, glm::vec2(size_));
  p.set(U::Eps, 0.5f * view.pixelMm);
  p.set(U::DegenerateTol, s.degenerateTol);
  p.set(U::Orthographic, view.orthographic ? 1 : 0);
  p.set(U::PixelMm, view.pixelMm);
  p.set(U::PixelMmPerDepth, view.pixelMmPerDepth);
  p.set(U::NoiseOrigin, s.noiseOrigin);
  p.set(U::Lod, s.lod);
  if (s.noiseBlend > 0.0f) p.set(U::NoiseBlend, s.noiseBlend);
  if (useFibres) {
    p.set(U::WorldToTex, fibres->worldToTex());
    p.set(U::LobeCount, fibres->lobes());
  } else {
    p.set(U::WorldToTex, field.worldToTex());
  }
  p.set(U::FaFloor, s.faFloor);
  if (hasBackground) {
    p.set(U::BackgroundWorldToTex, background->worldToTex());
    background->bind(unit(Unit::Background));
  }
  if (fray) {
    p.set(U::UncertaintyWorldToTex, s.uncertainty->worldToTex());
    p.set(U::Fray, s.fray);
    p.set(U::FrayCells, s.frayCells);
    s.uncertainty->bind(unit(Unit::Uncertainty));
  }
  p.use();
  if (useFibres)
    fibres->bind({unit(Unit::Lobe0), unit(Unit::Lobe1), unit(Unit::Lobe2)}, unit(Unit::FibreFa));
  else
    field.bind(unit(Unit::TensorA), unit(Unit::TensorB), unit(Unit::TensorEdge));
  bindTexture(Unit::Noise, noise.id());
  bindTexture(Unit::Geometry, geometry.geometry().id());
  glBindVertexArray(vao_.id());
  glBeginQuery(GL_SAMPLES_PASSED, samples_.id());
  if (haveData) glDrawArrays(GL_TRIANGLES, 0, 3);
  glEndQuery(GL_SAMPLES_PASSED);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
}

unsigned TensorStage::coveredPixels() const {
  GLuint n = 0;
  glGetQueryObjectuiv(samples_.id(), GL_QUERY_RESULT, &n);
  return n;
}

void ProjectionPass::resize(glm::ivec2 target) {
  geometry_.resize(target);
  tensor_.resize(target);
}

void ProjectionPass::run(const GpuMesh& mesh, const GpuTensorField& field, const Texture& noise,
                         const FrameView& view, const ProjectionSettings& s,
                         const GpuScalarVolume* background, const GpuFibreSet* fibres) {
  const bool haveData = s.fibres ? fibres && !fibres->empty() : !field.empty();
  geometry_.run(mesh, view, s.cullHidden && view.boundsInFront, haveData);
  tensor_.run(geometry_, field, noise, view, s, background, fibres);
}

void ProjectionPass::runTensor(const GpuTensorField& field, const Texture& noise, const FrameView& view,
                               const ProjectionSettings& s, const GpuScalarVolume* background,
                               const GpuFibreSet* fibres) {
  tensor_.run(geometry_, field, noise, view, s, background, fibres);
}

} // namespace dtf::render
