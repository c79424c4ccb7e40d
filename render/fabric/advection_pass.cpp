// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/advection_pass.h"

#include "io/model/error.h"
#include "render/gl_context.h"

#include <cmath>
#include <limits>
#include <vector>

namespace dtf::render {

namespace {
using Unit = AdvectionProgram::Unit;
using U = AdvectionProgram::Uniform;

std::vector<std::string> resetDefines(bool reproject = false) {
  std::vector<std::string> d = programDefines<AdvectionProgram>();
  d.push_back("RESET");
  if (reproject) d.push_back("REPROJECT");
  return d;
}

// Bits of AdvectionPass::restart_'s variants and of compute_'s.
constexpr unsigned kThird = 1u, kSilhouettes = 2u;
constexpr unsigned kComputeCount = 1u, kComputeThird = 2u, kComputeReset = 4u, kComputeSilhouettes = 8u,
                   kComputeIntegerStep = 16u;
// Bits of AdvectionPass::iteration_'s variants.
constexpr unsigned kCovered = 1u, kCount = 2u, kThreeFields = 4u, kIntegerStep = 8u;
// The compute program's image units per field: an iteration's target (the restart's first ping-pong
// texture) and the restart's second.
using Image = AdvectionComputeProgram::Image;
constexpr Image kNext[3] = {Image::Next1, Image::Next2, Image::Next3};
constexpr Image kOther[3] = {Image::Other1, Image::Other2, Image::Other3};

} // namespace

bool AdvectionSettings::integerStep() const {
  return stepPixels >= 0.0f && stepPixels <= 64.0f && stepPixels == std::floor(stepPixels);
}

AdvectionPass::AdvectionPass()
    : iteration_("fabric/advection.vert", "fabric/advection.frag", {"FAR_PLANE", "COUNT", "THIRD", "INTEGER_STEP"},
                 programDefines<AdvectionProgram>(), uniformNames<U>()),
      restart_("fabric/advection.vert", "fabric/advection.frag", {"THIRD", "SILHOUETTES"}, resetDefines(),
               uniformNames<U>()),
      reproject_("fabric/advection.vert", "fabric/advection.frag", resetDefines(true), uniformNames<U>()),
      compute_({{GL_COMPUTE_SHADER, "fabric/advection.comp"}}, {"COUNT", "THIRD", "RESET", "SILHOUETTES", "INTEGER_STEP"},
               programDefines<AdvectionComputeProgram>(), uniformNames<U>()),
      useCompute_(!softwareRasteriser()), vao_(createVertexArray()), counter_(createBuffer()) {
  const GLuint zero = 0;
  glNamedBufferStorage(counter_.id(), sizeof(GLuint), &zero, GL_DYNAMIC_STORAGE_BIT);
  // The restart every frame of a moving camera runs compiles with the pass.
  if (useCompute_)
    compute_.get(kComputeReset | kComputeSilhouettes);
  else
    restart_.get(kSilhouettes);
}

void AdvectionPass::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  const float blocked[4] = {kBlocked, 0, 0, 0};
  for (int i = 0; i < 2; ++i) {
    for (int c = 0; c < 3; ++c) {
      state_[i][c] = Texture::create2D(GL_R32F, target.x, target.y);
      state_[i][c].setFilter(GL_LINEAR, GL_LINEAR);
      // Beyond the edge the blocked outer ring repeats (cheaper than a border colour on llvmpipe).
      state_[i][c].setWrap(GL_CLAMP_TO_EDGE);
    }
    fbo_[i] = createFramebuffer();
    attachTargets(fbo_[i], {&state_[i][0], &state_[i][1]}, nullptr);
    fbo3_[i] = createFramebuffer();
    attachTargets(fbo3_[i], {&state_[i][0], &state_[i][1], &state_[i][2]}, nullptr);
    for (int c = 0; c < 3; ++c) glClearNamedFramebufferfv(fbo3_[i].id(), GL_COLOR, c, blocked);
  }
  resetFbo_ = createFramebuffer();
  attachTargets(resetFbo_, {&state_[0][0], &state_[0][1], &state_[1][0], &state_[1][1]}, nullptr);
  resetFbo3_ = createFramebuffer();
  attachTargets(resetFbo3_,
                {&state_[0][0], &state_[0][1], &state_[1][0], &state_[1][1], &state_[0][2], &state_[1][2]}, nullptr);
  resetEdgesFbo_ = createFramebuffer();
  resetEdgesFbo3_ = createFramebuffer();
  attachedEdges_ = 0;
  attachedDepth_ = 0;
  attachedColour_ = 0; // the draw framebuffers hold the old state textures
  drawDepth_ = 0;
  current_ = 0;
}

void AdvectionPass::setIterationUniforms(const ShaderProgram& program, const AdvectionSettings& s,
                                         bool countChanges, bool third) {
  program.set(U::K, s.k);
  program.set(U::Step, s.stepPixels);
  program.set(U::ComplementSecond, s.complementSecond ? 1 : 0);
  if (countChanges) program.set(U::Epsilon, s.epsilon);
  bindIterationInputs(program, countChanges, third);
}

void AdvectionPass::bindIterationInputs(const ShaderProgram& program, bool countChanges, bool third) {
  if (countChanges) {
    const GLuint zero = 0;
    glClearNamedBufferSubData(counter_.id(), GL_R32UI, 0, sizeof(GLuint), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  program.use();
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, unit(AdvectionProgram::Counter::Changed), counter_.id());
  bindTexture(Unit::Prev1, state_[current_][0].id());
  bindTexture(Unit::Prev2, state_[current_][1].id());
  if (third) bindTexture(Unit::Prev3, state_[current_][2].id());
  bindHere(third);
}

void AdvectionPass::bindHere(bool third) {
  using ReadImage = AdvectionBindings::ReadImage;
  constexpr ReadImage kHere[3] = {ReadImage::Here1, ReadImage::Here2, ReadImage::Here3};
  for (int c = 0; c < (third ? 3 : 2); ++c)
    bindReadImage(kHere[c], state_[current_][c], GL_R32F);
}

void AdvectionPass::step(const AdvectionSettings& s, bool countChanges, bool covered, bool third) {
  const int next = 1 - current_;
  glBindFramebuffer(GL_FRAMEBUFFER, (third ? fbo3_ : fbo_)[next].id());
  glViewport(0, 0, size_.x, size_.y);
  setIterationUniforms(iteration_.get((covered ? kCovered : 0u) | (countChanges ? kCount : 0u) |
                                      (third ? kThreeFields : 0u) | (s.integerStep() ? kIntegerStep : 0u)),
                       s, countChanges, third);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  current_ = next;
}

void AdvectionPass::dispatchStep(const AdvectionSettings& s, bool countChanges, bool third) {
  const int next = 1 - current_;
  const ShaderProgram& program = compute_.get((countChanges ? kComputeCount : 0u) | (third ? kComputeThird : 0u) |
                                              (s.integerStep() ? kComputeIntegerStep : 0u));
  for (int c = 0; c < (third ? 3 : 2); ++c)
    glBindImageTexture(unit(kNext[c]), state_[next][c].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  setIterationUniforms(program, s, countChanges, third);
  dispatchPerPixel(size_.x, size_.y);
  current_ = next;
}

void AdvectionPass::dispatchRestart(const ShaderProgram& program, const Texture& surface, const Texture* edges,
                                    bool third, bool complementSecond) {
  program.set(U::ComplementSecond, complementSecond ? 1 : 0);
  program.use();
  bindTexture(Unit::Surface, surface.id());
  bindReadImage(AdvectionBindings::ReadImage::Surface, surface, GL_RGBA32F);
  for (int c = 0; c < (third ? 3 : 2); ++c) {
    glBindImageTexture(unit(kNext[c]), state_[0][c].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(unit(kOther[c]), state_[1][c].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  }
  if (edges) glBindImageTexture(unit(Image::Edge), edges->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  dispatchPerPixel(size_.x, size_.y);
  current_ = 0;
}

void AdvectionPass::reset(const Texture& surface, const Texture& edges, int fields, bool complementSecond) {
  resize({surface.width(), surface.height()});
  bindTexture(Unit::Silhouette, edges.id());
  if (useCompute_) {
    dispatchRestart(compute_.get(kComputeReset | (fields >= 3 ? kComputeThird : 0u)), surface, nullptr, fields >= 3,
                    complementSecond);
    return;
  }
  const ShaderProgram& program = restart_.get(fields >= 3 ? kThird : 0u);
  drawRestart(program, fields >= 3 ? resetFbo3_ : resetFbo_, surface, complementSecond, fields >= 3 ? 6 : 4,
              false);
}

bool AdvectionPass::scissorCover(const Framebuffer& fbo, int states, bool edge) {
  if (cover_.z < 0 || cover_.w < 0 || (cover_.x <= 0 && cover_.y <= 0 && cover_.x + cover_.z >= size_.x &&
                                       cover_.y + cover_.w >= size_.y))
    return false;
  const float blocked[4] = {kBlocked, 0, 0, 0}, one[4] = {1, 0, 0, 0};
  for (int i = 0; i < states; ++i) glClearNamedFramebufferfv(fbo.id(), GL_COLOR, i, blocked);
  if (edge) glClearNamedFramebufferfv(fbo.id(), GL_COLOR, states, one);
  glEnable(GL_SCISSOR_TEST);
  glScissor(cover_.x, cover_.y, cover_.z, cover_.w);
  return true;
}

void AdvectionPass::drawRestart(const ShaderProgram& program, const Framebuffer& fbo, const Texture& surface,
                                bool complementSecond, int states, bool edge) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glViewport(0, 0, size_.x, size_.y);
  program.set(U::ComplementSecond, complementSecond ? 1 : 0);
  program.use();
  bindTexture(Unit::Surface, surface.id());
  bindReadImage(AdvectionBindings::ReadImage::Surface, surface, GL_RGBA32F);
  glBindVertexArray(vao_.id());
  const bool scissor = scissorCover(fbo, states, edge);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (scissor) glDisable(GL_SCISSOR_TEST);
  current_ = 0;
}

void AdvectionPass::resetFindingSilhouettes(const Texture& surface, const Texture& edges, float thresholdMm,
                                            float backgroundMm, int fields, bool complementSecond) {
  resize({surface.width(), surface.height()});
  if (edges.width() != size_.x || edges.height() != size_.y)
    throw GlError("AdvectionPass: the silhouette target's size differs from the surface's");
  if (useCompute_) {
    const ShaderProgram& program =
        compute_.get(kComputeReset | kComputeSilhouettes | (fields >= 3 ? kComputeThird : 0u));
    program.set(U::Threshold, thresholdMm);
    program.set(U::Background, backgroundMm);
    dispatchRestart(program, surface, &edges, fields >= 3, complementSecond);
    return;
  }
  if (edges.id() != attachedEdges_) {
    attachTargets(resetEdgesFbo_, {&state_[0][0], &state_[0][1], &state_[1][0], &state_[1][1], &edges}, nullptr);
    attachTargets(resetEdgesFbo3_,
                  {&state_[0][0], &state_[0][1], &state_[1][0], &state_[1][1], &state_[0][2], &state_[1][2], &edges},
                  nullptr);
    attachedEdges_ = edges.id();
  }
  const ShaderProgram& program = restart_.get(kSilhouettes | (fields >= 3 ? kThird : 0u));
  program.set(U::Threshold, thresholdMm);
  program.set(U::Background, backgroundMm);
  drawRestart(program, fields >= 3 ? resetEdgesFbo3_ : resetEdgesFbo_, surface, complementSecond,
              fields >= 3 ? 6 : 4, true);
}

void AdvectionPass::keepHistory(const Texture& surface) {
  if (size_.x < 1 || surface.width() != size_.x || surface.height() != size_.y) return;
  if (historySize_ != size_) {
    for (auto& t : history_) {
      t = Texture::create2D(GL_R32F, size_.x, size_.y);
      t.setFilter(GL_LINEAR, GL_LINEAR);
      t.setWrap(GL_CLAMP_TO_EDGE);
    }
    historySurface_ = Texture::create2D(GL_RGBA32F, size_.x, size_.y);
    historySurface_.setFilter(GL_NEAREST, GL_NEAREST); // read by texel
    historySize_ = size_;
  }
  for (int c = 0; c < 2; ++c)
    glCopyImageSubData(state_[current_][c].id(), GL_TEXTURE_2D, 0, 0, 0, 0, history_[c].id(), GL_TEXTURE_2D, 0,
                       0, 0, 0, size_.x, size_.y, 1);
  glCopyImageSubData(surface.id(), GL_TEXTURE_2D, 0, 0, 0, 0, historySurface_.id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                     size_.x, size_.y, 1);
}

void AdvectionPass::reproject(const Texture& surface, const Texture& edges, const Texture& depth,
                              const glm::mat4& windowToWorld, const glm::mat4& worldToPrevWindow,
                              const glm::mat4& worldToPrevEye, float depthTolMm, bool complementSecond) {
  resize({surface.width(), surface.height()});
  if (!hasHistory()) {
    reset(surface, edges, 2, complementSecond);
    return;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, resetFbo_.id());
  glViewport(0, 0, size_.x, size_.y);
  reproject_.set(U::ComplementSecond, complementSecond ? 1 : 0);
  reproject_.set(U::WindowToWorld, windowToWorld);
  reproject_.set(U::WorldToPrevWindow, worldToPrevWindow);
  reproject_.set(U::WorldToPrevEye, worldToPrevEye);
  reproject_.set(U::DepthTol, depthTolMm);
  reproject_.use();
  bindTexture(Unit::Surface, surface.id());
  bindReadImage(AdvectionBindings::ReadImage::Surface, surface, GL_RGBA32F);
  bindTexture(Unit::Silhouette, edges.id());
  bindTexture(Unit::Prev1, history_[0].id());
  bindTexture(Unit::Prev2, history_[1].id());
  bindTexture(Unit::HistorySurface, historySurface_.id());
  bindTexture(Unit::Depth, depth.id());
  glBindVertexArray(vao_.id());
  const bool scissor = scissorCover(resetFbo_, 4, false);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (scissor) glDisable(GL_SCISSOR_TEST);
  current_ = 0;
}

void AdvectionPass::bindVectors(const Texture& vectors, int fields) {
  const bool third = fields >= 3;
  const GLenum layout = third ? GL_RGBA32UI : GL_RG32UI;
  if (vectors.format() != layout)
    throw GlError(third ? "AdvectionPass: three fields need the RGBA32UI vectors with the third direction"
                        : "AdvectionPass: two fields need the RG32UI vectors");
  bindReadImage(AdvectionBindings::ReadImage::Vectors, vectors, layout);
}

void AdvectionPass::attachDepth(GLuint depth) {
  if (depth == attachedDepth_) return;
  for (auto& f : fbo_) glNamedFramebufferTexture(f.id(), GL_DEPTH_ATTACHMENT, depth, 0);
  for (auto& f : fbo3_) glNamedFramebufferTexture(f.id(), GL_DEPTH_ATTACHMENT, depth, 0);
  attachedDepth_ = depth;
}

void AdvectionPass::iterate(const Texture& vectors, const AdvectionSettings& s, int count, bool countChanges,
                            const Texture* depth, int fields) {
  if (count <= 0) return;
  const bool third = fields >= 3;
  bindVectors(vectors, fields);
  counted_ = countChanges;
  if (useCompute_) {
    // As for the fragment variants below: both compile before any frame needs them.
    const unsigned variant = (third ? kComputeThird : 0u) | (s.integerStep() ? kComputeIntegerStep : 0u);
    compute_.get(variant);
    compute_.get(variant | kComputeCount);
    for (int i = 0; i < count; ++i) dispatchStep(s, countChanges && i == count - 1, third);
    return;
  }
  const bool covered = depth && depth->width() == size_.x && depth->height() == size_.y;
  attachDepth(covered ? depth->id() : 0);
  if (covered) coveredPixelsOnly(true);
  // The counted variant (still frames) and the uncounted one (frames that restarted) compile together, so
  // no frame compiles a program (and allocates) when the camera starts or stops moving.
  const unsigned variant =
      (covered ? kCovered : 0u) | (third ? kThreeFields : 0u) | (s.integerStep() ? kIntegerStep : 0u);
  iteration_.get(variant);
  iteration_.get(variant | kCount);
  for (int i = 0; i < count; ++i) step(s, countChanges && i == count - 1, covered, third);
  if (covered) coveredPixelsOnly(false);
}

void AdvectionPass::coveredPixelsOnly(bool on) {
  if (on) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER); // the triangle lies at the far plane: it passes where the surface is
    glDepthMask(GL_FALSE);
  } else {
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
  }
}

void AdvectionPass::iterateDrawing(const ShaderProgram& program, const Texture& vectors, bool countChanges,
                                   const Texture& depth, int fields, const Texture& colour) {
  if (useCompute_) throw GlError("AdvectionPass: iterateDrawing draws fragment passes, not compute ones");
  if (depth.width() != size_.x || depth.height() != size_.y || colour.width() != size_.x ||
      colour.height() != size_.y)
    throw GlError("AdvectionPass: iterateDrawing's depth and colour targets must have the state's size");
  const bool third = fields >= 3;
  bindVectors(vectors, fields);
  counted_ = countChanges;
  // The framebuffers are attached when the colour or depth target changes, not per frame.
  if (colour.id() != attachedColour_ || depth.id() != drawDepth_) {
    for (int i = 0; i < 2; ++i) {
      drawFbo_[i] = createFramebuffer();
      attachTargets(drawFbo_[i], {&colour, &state_[i][0], &state_[i][1]}, &depth);
      drawFbo3_[i] = createFramebuffer();
      attachTargets(drawFbo3_[i], {&colour, &state_[i][0], &state_[i][1], &state_[i][2]}, &depth);
    }
    attachedColour_ = colour.id();
    drawDepth_ = depth.id();
  }
  const int next = 1 - current_;
  glBindFramebuffer(GL_FRAMEBUFFER, (third ? drawFbo3_ : drawFbo_)[next].id());
  glViewport(0, 0, size_.x, size_.y);
  coveredPixelsOnly(true);
  bindIterationInputs(program, countChanges, third);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  coveredPixelsOnly(false);
  current_ = next;
}

void AdvectionPass::setFields(const float* rg) {
  std::vector<float> p(static_cast<std::size_t>(size_.x) * size_.y);
  for (int c = 0; c < 2; ++c) {
    const Texture& t = state_[current_][c];
    glGetTextureImage(t.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(p.size() * sizeof(float)), p.data());
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p[i] != kBlocked) p[i] = rg[i * 2 + c];
    glTextureSubImage2D(t.id(), 0, 0, 0, size_.x, size_.y, GL_RED, GL_FLOAT, p.data());
  }
}

std::vector<float> AdvectionPass::readFields() const {
  const std::size_t n = static_cast<std::size_t>(size_.x) * size_.y;
  std::vector<float> p(n), rg(n * 2);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  for (int c = 0; c < 2; ++c) {
    glGetTextureImage(state_[current_][c].id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(n * sizeof(float)),
                      p.data());
    for (std::size_t i = 0; i < n; ++i) rg[i * 2 + c] = p[i];
  }
  return rg;
}

unsigned AdvectionPass::changedPixels() const {
  if (!counted_) return std::numeric_limits<unsigned>::max();
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint v = 0;
  glGetNamedBufferSubData(counter_.id(), 0, sizeof(GLuint), &v);
  return v;
}

} // namespace dtf::render
