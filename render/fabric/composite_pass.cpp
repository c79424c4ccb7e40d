#include "render/fabric/composite_pass.h"

namespace dtf::render {

CompositePass::CompositePass()
    : programs_("common/fullscreen.vert", "fabric/composite.frag",
                {"MEDICAL", "SILHOUETTES", "BACKGROUND", "DEPTH_COLOUR", "SHARPEN", "FIBRES", "WINDOW_DEPTH"}),
      vao_(createVertexArray()) {
  programs_.get(3); // medical with silhouettes, the default, compiles with the pass
}

void CompositePass::run(const CompositeInputs& in, const FrameView& view, const CompositeSettings& s) {
  const unsigned mask = (s.mode == ColourMode::Medical ? 1u : 0u) | (s.silhouettes ? 2u : 0u) |
                        (s.background ? 4u : 0u) | (s.depthColour > 0.0f ? 8u : 0u) | (s.sharpen > 0.0f ? 16u : 0u) |
                        (s.mode == ColourMode::Fibres && in.fibres ? 32u : 0u) |
                        (s.windowDepth && in.depth ? 64u : 0u);
  const ShaderProgram& p = programs_.get(mask);
  glProgramUniform2i(p.id(), p.location("u_guard"), view.guard, view.guard);
  glProgramUniform2i(p.id(), p.location("u_origin"), s.origin.x, s.origin.y);
  p.set("u_scale", glm::vec2(view.internal) / glm::vec2(glm::max(view.viewport, glm::ivec2(1))));
  p.set("u_eyeDepth", view.eyeDepth);
  p.set("u_r", s.r);
  p.set("u_contrast", s.contrast);
  p.set("u_lightWeight", s.lightWeight);
  p.set("u_lightMix", s.lightMix);
  p.set("u_lighting", s.lighting ? 1 : 0);
  if (s.depthColour > 0.0f) {
    p.set("u_depthColour", s.depthColour);
    p.set("u_depthRange", view.depthRange);
  }
  if (s.sharpen > 0.0f) p.set("u_sharpen", s.sharpen);
  p.set("u_secondaryRatio", s.secondaryRatio);
  p.set("u_secondaryFa", s.secondaryFa);
  p.set("u_fadeOutOfPlane", s.fadeOutOfPlane);
  p.use();
  glBindTextureUnit(0, in.p1->id());
  glBindTextureUnit(3, in.p2->id());
  glBindTextureUnit(1, in.surface->id());
  glBindTextureUnit(2, in.edges->id());
  glBindTextureUnit(4, in.eigen->id());
  glBindTextureUnit(5, in.lambda->id());
  if (s.mode == ColourMode::Fibres && in.fibres) {
    glBindTextureUnit(6, in.p3->id());
    glBindTextureUnit(7, in.fibres->id());
  }
  if (s.windowDepth && in.depth) glBindTextureUnit(8, in.depth->id());
  glViewport(s.origin.x, s.origin.y, view.viewport.x, view.viewport.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(s.windowDepth && in.depth ? GL_LEQUAL : GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
