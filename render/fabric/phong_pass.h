// SPDX-License-Identifier: GPL-3.0-or-later
// Plain Blinn-Phong rendering of a mesh into the bound framebuffer: the baseline the fabric is
// benchmarked against (paper Table 1) and the look of surfaces without tensor data.
#pragma once

#include "render/fabric/frame_view.h"
#include "render/gpu_scene.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

namespace dtf::render {

class PhongPass {
public:
  PhongPass();
  // Draws with depth test into the bound framebuffer at the viewport size (no guard border).
  void run(const GpuMesh& mesh, const FrameView& view, const glm::vec3& colour);

private:
  ShaderProgram program_;
};

} // namespace dtf::render
