#include "render/fabric/phong_pass.h"

namespace dtf::render {

PhongPass::PhongPass() : program_("fabric/phong.vert", "fabric/phong.frag") {}

void PhongPass::run(const GpuMesh& mesh, const FrameView& view, const glm::vec3& colour) {
  program_.set("u_viewProj", view.viewProjViewport);
  program_.set("u_view", view.view);
  program_.set("u_viewRot", view.viewRot);
  program_.set("u_orthographic", view.orthographic ? 1 : 0);
  program_.set("u_colour", colour);
  program_.use();
  glViewport(0, 0, view.viewport.x, view.viewport.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  mesh.drawVisible(view.boundsInFront);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
