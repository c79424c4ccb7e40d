// SPDX-License-Identifier: GPL-3.0-or-later
// Pass 2 of the fabric (paper §2.4, Eq. 10): silhouettes from the 3x3 Laplacian of the linear depth.
//   input : projection surface texture (.b linear depth mm, .a coverage)
//   output: edge R8 (1 on silhouettes and off the surface, else 0; border 1), the guarded target's size
#pragma once

#include "render/gl_objects.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

#include <glm/glm.hpp>

namespace dtf::render {

class SilhouettePass {
public:
  SilhouettePass();
  void resize(glm::ivec2 target);
  // thresholdMm: |Laplacian| of depth above which a pixel is an edge; backgroundMm: depth of empty pixels.
  // With the projection's depth buffer given, only covered pixels are shaded (the rest are set to 1 by a
  // clear), which skips the background on a software rasteriser.
  void run(const Texture& surface, float thresholdMm, float backgroundMm, const Texture* depth = nullptr);
  // Clears the edges to 0 (silhouettes off).
  void clear();
  const Texture& edges() const { return edges_; }

private:
  ShaderProgram program_, covered_;
  VertexArray vao_;
  Framebuffer fbo_;
  GLuint attachedDepth_ = 0;
  Texture edges_;
  glm::ivec2 size_{0};
};

} // namespace dtf::render
