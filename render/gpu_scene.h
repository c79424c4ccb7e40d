// SPDX-License-Identifier: GPL-3.0-or-later
// GPU copies of the scene's value types: a Mesh as vertex/index buffers, a TensorField as two RGBA32F 3D
// textures with its world -> texture transform, and the reaction-diffusion noise as a mipmapped, repeating
// 2D texture. Uploaded once per change of the data, never per frame.
#pragma once

#include "io/model/geometry.h"
#include "io/model/tensor_field.h"
#include "render/gl_objects.h"
#include "render/noise.h"

#include <glm/glm.hpp>

namespace dtf::render {

class GpuMesh {
public:
  GpuMesh() = default;
  // Uploads positions and normals (computed when missing) and the indices. Throws GlError.
  void upload(const Mesh& mesh);
  // Draws all triangles with the currently bound program.
  void draw() const;
  std::size_t triangleCount() const { return indexCount_ / 3; }
  glm::vec3 boundsLo() const { return lo_; }
  glm::vec3 boundsHi() const { return hi_; }
  bool empty() const { return indexCount_ == 0; }
  // Mesh::isClosedOutward() of the uploaded mesh: back faces may be culled when seen from outside.
  bool closedOutward() const { return closedOutward_; }
  // Draws with back faces culled when the mesh is closed and outward and `viewOutside` (the whole mesh
  // lies beyond the near plane, so no back face can be seen through a cut): the same image for half the
  // rasterisation work.
  void drawVisible(bool viewOutside) const;

private:
  VertexArray vao_;
  Buffer vertices_, indices_;
  std::size_t indexCount_ = 0;
  glm::vec3 lo_{0.0f}, hi_{0.0f};
  bool closedOutward_ = false;
};

class GpuTensorField {
public:
  GpuTensorField() = default;
  // Texture A: xx xy xz yy; texture B: yz zz FA valid (world RAS, mm^2/s); the edge texture: the data mask
  // blurred by a 3x3x3 binomial kernel (sigma about 0.7 voxel), whose 0.5 contour is the data's smooth
  // outline (the raw mask's trilinear contour cuts voxel corners at 45 degrees). Throws GlError when the
  // grid exceeds GL_MAX_3D_TEXTURE_SIZE or the GPU runs out of memory for the textures (GL_OUT_OF_MEMORY).
  void upload(const TensorField& field);
  // Binds texture A to `unitA`, B to `unitB` (a program's UNIT_TENSOR_A and UNIT_TENSOR_B), the edge texture
  // to `unitEdge` (UNIT_TENSOR_EDGE).
  void bind(GLuint unitA, GLuint unitB, GLuint unitEdge) const;
  // World RAS mm -> 3D texture coordinates (voxel centres at (i + 0.5) / dims).
  const glm::mat4& worldToTex() const { return worldToTex_; }
  bool empty() const { return !a_; }

private:
  Texture a_, b_, edge_;
  glm::mat4 worldToTex_{1.0f};
};

// A scalar volume (FA, MD, a T1) shown in grey where the surface has no tensor data: one R32F 3D texture
// holding (value - lo) / (hi - lo) clamped to [0, 1], black outside the grid.
class GpuScalarVolume {
public:
  GpuScalarVolume() = default;
  // Uploads component 0 windowed to [lo, hi] (channels 1), or components 0..2 as RGB (channels 3; a volume
  // with fewer components repeats its component 0). Throws GlError when the grid does not fit a 3D texture.
  void upload(const ScalarVolume& volume, float lo, float hi, int channels = 1);
  void clear() { texture_ = Texture(); }
  // Binds the texture to `unit`.
  void bind(GLuint unit) const;
  const glm::mat4& worldToTex() const { return worldToTex_; }
  bool empty() const { return !texture_; }

private:
  Texture texture_;
  glm::mat4 worldToTex_{1.0f};
};

// The noise tile as a single-channel float texture with mipmaps and GL_REPEAT (seamless).
Texture uploadNoise(const NoiseTile& tile);

} // namespace dtf::render
