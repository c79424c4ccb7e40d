// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/composite_pass.h"

#include "io/model/error.h"

namespace dtf::render {

namespace {
using Unit = CompositeProgram::Unit;
using Image = CompositeProgram::Image;
using U = CompositeProgram::Uniform;

// Bits of CompositePass::programs_.
constexpr unsigned kMedical = 1u, kSilhouettes = 2u, kBackground = 4u, kDepthColour = 8u, kSharpen = 16u,
                   kFibres = 32u, kWindowDepth = 64u, kAnatomy = 128u, kDecFa = 256u, kFade = 512u,
                   kFarPlane = 1024u, kOverClear = 2048u, kAdvect = 4096u, kThird = 8192u, kCount = 16384u,
                   kIntegerStep = 32768u;

// Scissors to the viewport pixels the scene can cover (FrameView::coverRect), the viewport's lower left at
// `origin`: a software rasteriser would run the whole shader on the rest. False where that is not known.
bool scissorToCover(const FrameView& view, glm::ivec2 origin) {
  const glm::ivec4 rect = view.coverRect;
  if (rect.z < 0 || rect.w < 0) return false;
  glEnable(GL_SCISSOR_TEST);
  glScissor(origin.x + rect.x, origin.y + rect.y, rect.z, rect.w);
  return true;
}
} // namespace

CompositePass::CompositePass()
    : programs_("fabric/composite.vert", "fabric/composite.frag",
                {"MEDICAL", "SILHOUETTES", "BACKGROUND", "DEPTH_COLOUR", "SHARPEN", "FIBRES", "WINDOW_DEPTH",
                 "ANATOMY", "DEC_FA", "FADE", "FAR_PLANE", "OVER_CLEAR", "ADVECT", "THIRD", "COUNT", "INTEGER_STEP"},
                programDefines<CompositeProgram>(), uniformNames<U>()),
      depthPrograms_("fabric/composite.vert", "fabric/composite_depth.frag", {"BACKGROUND"},
                     programDefines<CompositeDepthProgram>(), uniformNames<CompositeDepthProgram::Uniform>()),
      vao_(createVertexArray()), texelSampler_(createTexelSampler()) {
  programs_.get(kMedical | kSilhouettes); // the default compiles with the pass
}

unsigned CompositePass::lookMask(const CompositeSettings& s, bool fibres) {
  const bool medical = s.mode == ColourMode::Medical;
  return (medical ? kMedical : 0u) | (s.silhouettes ? kSilhouettes : 0u) | (s.background ? kBackground : 0u) |
         (s.depthColour > 0.0f ? kDepthColour : 0u) | (s.mode == ColourMode::Fibres && fibres ? kFibres : 0u) |
         (s.anatomy ? kAnatomy : 0u) | (medical && s.decFa ? kDecFa : 0u) |
         (medical && s.fadeOutOfPlane > 0.0f ? kFade : 0u);
}

void CompositePass::setUniforms(const ShaderProgram& p, const FrameView& view, const CompositeSettings& s,
                                glm::ivec2 target) const {
  p.set(U::Guard, glm::ivec2(view.guard));
  p.set(U::Target, target);
  p.set(U::Origin, s.origin);
  p.set(U::Scale, glm::vec2(view.internal) / glm::vec2(glm::max(view.viewport, glm::ivec2(1))));
  p.set(U::EyeDepth, view.eyeDepth);
  p.set(U::R, s.r);
  p.set(U::Contrast, s.contrast);
  p.set(U::LightWeight, s.lightWeight);
  p.set(U::LightMix, s.lightMix);
  p.set(U::Lighting, s.lighting ? 1 : 0);
  if (s.depthColour > 0.0f) {
    p.set(U::DepthColour, s.depthColour);
    p.set(U::DepthRange, view.depthRange);
  }
  if (s.sharpen > 0.0f) p.set(U::Sharpen, s.sharpen);
  p.set(U::SecondaryRatio, s.secondaryRatio);
  p.set(U::SecondaryFa, s.secondaryFa);
  if (s.fadeOutOfPlane > 0.0f) p.set(U::FadeOutOfPlane, s.fadeOutOfPlane);
  if (s.anatomy) p.set(U::OpacityFa, s.opacityFa);
  p.set(U::ClearColour, s.clearColour);
}

void CompositePass::bindInputs(const CompositeInputs& in, const CompositeSettings& s, const Texture* light) const {
  if (light)
    bindReadImage(Image::Light, *light, GL_R16);
  else
    bindReadImage(Image::Surface, *in.surface, GL_RGBA32F);
  bindReadImage(Image::Eigen, *in.eigen, GL_RGBA8);
  bindReadImage(Image::Lambda, *in.lambda, GL_RGBA8);
  if (s.mode == ColourMode::Fibres && in.fibres) bindReadImage(Image::Fibres, *in.fibres, GL_RGBA32UI);
}

void CompositePass::run(const CompositeInputs& in, const FrameView& view, const CompositeSettings& s) {
  const bool windowDepth = s.depth == CompositeDepth::Window && in.depth;
  const bool present = s.depth == CompositeDepth::Present;
  // With a background volume, or a host's surface drawn whole, every pixel drawn has alpha 1: nothing to lay
  // over what is beneath.
  const bool opaque = s.background || windowDepth;
  const bool overClear = s.overClear && !opaque;
  const unsigned mask = lookMask(s, in.fibres != nullptr) | (s.sharpen > 0.0f ? kSharpen : 0u) |
                        (windowDepth ? kWindowDepth : 0u) | (present ? kFarPlane : 0u) |
                        (overClear ? kOverClear : 0u);
  const ShaderProgram& p = programs_.get(mask);
  setUniforms(p, view, s, glm::ivec2(in.surface->width(), in.surface->height()));
  p.use();
  using ReadImage = CompositeProgram::ReadImage;
  bindReadImage(ReadImage::Here1, *in.p1, GL_R32F);
  bindReadImage(ReadImage::Here2, *in.p2, GL_R32F);
  if (s.mode == ColourMode::Fibres && in.fibres) bindReadImage(ReadImage::Here3, *in.p3, GL_R32F);
  bindInputs(in, s);
  if (windowDepth) {
    bindTexture(Unit::Depth, in.depth->id());
    glBindSampler(unit(Unit::Depth), texelSampler_.id()); // read texel by texel, no depth comparison
  }
  glViewport(s.origin.x, s.origin.y, view.viewport.x, view.viewport.y);
  const bool scissor = scissorToCover(view, s.origin);
  glEnable(GL_DEPTH_TEST);
  // Present: the triangle lies at the far plane, so GL_GREATER passes exactly where the surface is.
  glDepthFunc(present ? GL_GREATER : windowDepth ? GL_LEQUAL : GL_ALWAYS);
  glDepthMask(present ? GL_FALSE : GL_TRUE);
  // The data's anti-aliased edge: straight alpha over what is beneath (the clear colour, a host's image),
  // blended, or in the shader over a known clear colour (OVER_CLEAR). Opaque pixels need neither: blending
  // would give the source unchanged at the cost of reading the framebuffer.
  if (opaque || overClear) {
    glDisable(GL_BLEND);
  } else {
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glBlendEquation(GL_FUNC_ADD);
  }
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (windowDepth) glBindSampler(unit(Unit::Depth), 0);
  if (scissor) glDisable(GL_SCISSOR_TEST);
  glBlendFunc(GL_ONE, GL_ZERO);
  glDisable(GL_BLEND);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE); // clears honour the mask
  glDisable(GL_DEPTH_TEST);
}

const ShaderProgram& CompositePass::advecting(const CompositeInputs& in, const FrameView& view,
                                              const CompositeSettings& s, const AdvectionSettings& iteration,
                                              bool countChanges, int fields) {
  if (!in.light) throw GlError("CompositePass::advecting needs the projection's light target");
  const unsigned mask = lookMask(s, in.fibres != nullptr) | kFarPlane | kAdvect | (fields >= 3 ? kThird : 0u) |
                        (iteration.integerStep() ? kIntegerStep : 0u);
  // The counted variant (still frames) and the uncounted one compile together, so no frame compiles a
  // program (and allocates) when the camera starts or stops moving.
  programs_.get(mask);
  programs_.get(mask | kCount);
  const ShaderProgram& p = programs_.get(mask | (countChanges ? kCount : 0u));
  setUniforms(p, view, s, glm::ivec2(in.surface->width(), in.surface->height()));
  p.set(U::K, iteration.k);
  p.set(U::Step, iteration.stepPixels);
  p.set(U::ComplementSecond, iteration.complementSecond ? 1 : 0);
  if (countChanges) p.set(U::Epsilon, iteration.epsilon);
  bindInputs(in, s, s.depthColour > 0.0f ? nullptr : in.light);
  return p;
}

void CompositePass::runDepth(const CompositeInputs& in, const FrameView& view, bool background) {
  using DepthU = CompositeDepthProgram::Uniform;
  const ShaderProgram& p = depthPrograms_.get(background ? 1u : 0u);
  p.set(DepthU::Guard, glm::ivec2(view.guard));
  p.set(DepthU::EyeDepth, view.eyeDepth);
  p.use();
  bindReadImage(Image::Surface, *in.surface, GL_RGBA32F);
  bindReadImage(Image::Lambda, *in.lambda, GL_RGBA8);
  glViewport(0, 0, view.viewport.x, view.viewport.y);
  const bool scissor = scissorToCover(view, glm::ivec2(0));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (scissor) glDisable(GL_SCISSOR_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
