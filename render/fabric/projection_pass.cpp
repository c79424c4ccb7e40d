// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/projection_pass.h"

#include "render/gl_context.h"

namespace dtf::render {

namespace {
using Unit = ProjectionProgram::Unit;
using U = ProjectionProgram::Uniform;
} // namespace

TensorStage::TensorStage()
    : program_("fabric/projection.vert", "fabric/projection.frag",
               {"WITH_PRINCIPAL", "NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY", "ALONG"},
               programDefines<ProjectionProgram>(), uniformNames<U>()),
      computeProgram_({{GL_COMPUTE_SHADER, "fabric/projection.comp"}},
                      {"WITH_PRINCIPAL", "NOISE_BLEND", "BACKGROUND", "FIBRES", "UNCERTAINTY", "ALONG"},
                      programDefines<ProjectionComputeProgram>(), uniformNames<U>()),
      compute_(!softwareRasteriser()), vao_(createVertexArray()), samples_(createQuery(GL_SAMPLES_PASSED)),
      covered_(createBuffer()) {
  const GLuint zero = 0;
  glNamedBufferStorage(covered_.id(), sizeof(GLuint), &zero, GL_DYNAMIC_STORAGE_BIT);
  // The default variant compiles with the pass, so a broken shader fails early.
  (compute_ ? computeProgram_ : program_).get(1);
}

void TensorStage::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  vectors_ = Texture::create2D(GL_RG32UI, target.x, target.y);
  surface_ = Texture::create2D(GL_RGBA32F, target.x, target.y);
  eigen_ = Texture::create2D(GL_RGBA8, target.x, target.y);
  lambda_ = Texture::create2D(GL_RGBA8, target.x, target.y);
  light_ = Texture::create2D(GL_R16, target.x, target.y);
  fibres_ = Texture::create2D(GL_RGBA32UI, target.x, target.y);
  vectors3_ = Texture::create2D(GL_RGBA32UI, target.x, target.y);
  for (Texture* t : {&vectors_, &surface_, &eigen_, &lambda_, &light_, &fibres_, &vectors3_})
    t->setFilter(GL_NEAREST, GL_NEAREST);
  fbo_ = createFramebuffer();
  attachTargets(fbo_, {&vectors_, &surface_, &eigen_, &lambda_, &light_}, nullptr);
  fibreFbo_ = createFramebuffer();
  attachTargets(fibreFbo_, {&vectors_, &surface_, &eigen_, &lambda_, &light_, &fibres_, &vectors3_}, nullptr);
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
  const bool hasBackground = background && !background->empty();
  const bool fray = s.uncertainty && !s.uncertainty->empty() && s.fray > 0.0f;
  const bool along = s.along && !s.along->empty();
  const unsigned variant = (s.principal && !useFibres ? 1u : 0u) | (s.noiseBlend > 0.0f ? 2u : 0u) |
                           (hasBackground ? 4u : 0u) | (useFibres ? 8u : 0u) | (fray ? 16u : 0u) |
                           (along ? 32u : 0u);
  lastCompute_ = compute_;
  if (compute_) {
    prepare(computeProgram_.get(variant), field, noise, view, s, background, fibres, useFibres, hasBackground, fray);
    bindReadImage(ProjectionProgram::ReadImage::Geometry, geometry.geometry(), GL_RG32UI);
    dispatch(geometry, haveData, useFibres);
    return;
  }
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
  prepare(program_.get(variant), field, noise, view, s, background, fibres, useFibres, hasBackground, fray);
  bindReadImage(ProjectionProgram::ReadImage::Geometry, geometry.geometry(), GL_RG32UI);
  glBindVertexArray(vao_.id());
  glBeginQuery(GL_SAMPLES_PASSED, samples_.id());
  if (haveData) glDrawArrays(GL_TRIANGLES, 0, 3);
  glEndQuery(GL_SAMPLES_PASSED);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
}

void TensorStage::prepare(const ShaderProgram& p, const GpuTensorField& field, const Texture& noise,
                          const FrameView& view, const ProjectionSettings& s, const GpuScalarVolume* background,
                          const GpuFibreSet* fibres, bool useFibres, bool hasBackground, bool fray) const {
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
  if (s.along && !s.along->empty()) {
    // The weight's grid is world axis-aligned: its world-to-texture map is a scale and an offset.
    const glm::mat4& m = s.along->worldToTex();
    p.set(U::AlongScale, glm::vec3(m[0][0], m[1][1], m[2][2]));
    p.set(U::AlongOffset, glm::vec3(m[3]));
    s.along->bind(unit(Unit::Along));
  }
  if (fray) {
    p.set(U::UncertaintyWorldToTex, s.uncertainty->worldToTex());
    p.set(U::Fray, s.fray);
    p.set(U::FrayCells, s.frayCells);
    s.uncertainty->bind(unit(Unit::Uncertainty));
  }
  p.use();
  if (useFibres)
    fibres->bind({unit(Unit::Lobe0), unit(Unit::Lobe1), unit(Unit::Lobe2)},
                 {unit(Unit::Lobe0B), unit(Unit::Lobe1B), unit(Unit::Lobe2B)}, unit(Unit::FibreFa));
  else
    field.bind(unit(Unit::TensorA), unit(Unit::TensorB), unit(Unit::TensorEdge));
  bindTexture(Unit::Noise, noise.id());
}

void TensorStage::dispatch(const GeometryStage& geometry, bool haveData, bool useFibres) {
  using Image = ProjectionComputeProgram::Image;
  const GLuint zero = 0;
  glClearNamedBufferSubData(covered_.id(), GL_R32UI, 0, sizeof(GLuint), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  if (!haveData) { // nothing covered, as the fragment pass's cleared surface target says
    const float none[4] = {0, 0, 0, 0};
    glClearTexImage(surface_.id(), 0, GL_RGBA, GL_FLOAT, none);
    return;
  }
  glBindTextureUnit(ProjectionComputeProgram::kDepthUnit, geometry.depth().id());
  glBindImageTexture(unit(Image::Vectors), vectors_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32UI);
  glBindImageTexture(unit(Image::Surface), surface_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(unit(Image::Eigen), eigen_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  glBindImageTexture(unit(Image::Lambda), lambda_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  glBindImageTexture(unit(Image::Light), light_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16);
  if (useFibres) {
    glBindImageTexture(unit(Image::Fibres), fibres_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glBindImageTexture(unit(Image::Vectors3), vectors3_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unit(ProjectionComputeProgram::Buffer::Covered), covered_.id());
  dispatchPerPixel(size_.x, size_.y); // coveredPixels() reads the count after its barrier
}

unsigned TensorStage::coveredPixels() const {
  GLuint n = 0;
  if (lastCompute_) {
    glGetNamedBufferSubData(covered_.id(), 0, sizeof(GLuint), &n);
    return n;
  }
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
