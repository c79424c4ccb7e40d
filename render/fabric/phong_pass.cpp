// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/phong_pass.h"

namespace dtf::render {

using U = PhongProgram::Uniform;

PhongPass::PhongPass()
    : program_("fabric/phong.vert", "fabric/phong.frag", programDefines<PhongProgram>(), uniformNames<U>()) {}

void PhongPass::run(const GpuMesh& mesh, const FrameView& view, const glm::vec3& colour) {
  program_.set(U::ViewProj, view.viewProjViewport);
  program_.set(U::View, view.view);
  program_.set(U::ViewRot, view.viewRot);
  program_.set(U::Orthographic, view.orthographic ? 1 : 0);
  program_.set(U::Colour, colour);
  program_.use();
  glViewport(0, 0, view.viewport.x, view.viewport.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  mesh.drawVisible(view.boundsInFront);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
