#include "render/fabric/composite_pass.h"

namespace dtf::render {

namespace {
using Unit = CompositeProgram::Unit;
using Image = CompositeProgram::Image;
using U = CompositeProgram::Uniform;

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
                 "ANATOMY", "DEC_FA", "FADE", "FAR_PLANE", "OVER_CLEAR"},
                programDefines<CompositeProgram>(), uniformNames<U>()),
      depthPrograms_("fabric/composite.vert", "fabric/composite_depth.frag", {"BACKGROUND"},
                     programDefines<CompositeDepthProgram>(), uniformNames<CompositeDepthProgram::Uniform>()),
      vao_(createVertexArray()), texelSampler_(createTexelSampler()) {
  programs_.get(3); // medical with silhouettes, the default, compiles with the pass
}

void CompositePass::run(const CompositeInputs& in, const FrameView& view, const CompositeSettings& s) {
  const bool windowDepth = s.depth == CompositeDepth::Window && in.depth;
  const bool present = s.depth == CompositeDepth::Present;
  // With a background volume, or a host's surface drawn whole, every pixel drawn has alpha 1: nothing to lay
  // over what is beneath.
  const bool opaque = s.background || windowDepth;
  const bool overClear = s.overClear && !opaque;
  const unsigned mask = (s.mode == ColourMode::Medical ? 1u : 0u) | (s.silhouettes ? 2u : 0u) |
                        (s.background ? 4u : 0u) | (s.depthColour > 0.0f ? 8u : 0u) | (s.sharpen > 0.0f ? 16u : 0u) |
                        (s.mode == ColourMode::Fibres && in.fibres ? 32u : 0u) |
                        (windowDepth ? 64u : 0u) | (s.anatomy ? 128u : 0u) | (present ? 1024u : 0u) |
                        (s.mode == ColourMode::Medical && s.decFa ? 256u : 0u) |
                        (s.mode == ColourMode::Medical && s.fadeOutOfPlane > 0.0f ? 512u : 0u) |
                        (overClear ? 2048u : 0u);
  const ShaderProgram& p = programs_.get(mask);
  p.set(U::Guard, glm::ivec2(view.guard));
  p.set(U::Target, glm::ivec2(in.p1->width(), in.p1->height()));
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
  if (overClear) p.set(U::ClearColour, s.clearColour);
  p.use();
  bindReadImage(Image::P1, *in.p1, GL_R32F);
  bindReadImage(Image::P2, *in.p2, GL_R32F);
  bindReadImage(Image::Surface, *in.surface, GL_RGBA32F);
  bindReadImage(Image::Eigen, *in.eigen, GL_RGBA8);
  bindReadImage(Image::Lambda, *in.lambda, GL_RGBA8);
  if (s.mode == ColourMode::Fibres && in.fibres) {
    bindReadImage(Image::P3, *in.p3, GL_R32F);
    bindReadImage(Image::Fibres, *in.fibres, GL_RGBA32UI);
  }
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
