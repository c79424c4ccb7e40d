// GPU copy of a FibreSet for the multi-population fabric: continuousSlots of the set (lobes below the
// relative threshold dropped, the rest matched between neighbouring voxels and sign-aligned) as up to three
// RGBA32F 3D textures, one per slot (amplitude x unit world direction, amplitude; trilinear, 0 outside),
// and an RG32F texture (FA of a paired tensor or 1, 1 where the voxel has fibres). See
// shaders/common/fibre_field.glsl. Uploaded once per change of the data or threshold, never per frame.
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/volume.h"
#include "render/gl_objects.h"

#include <glm/glm.hpp>

#include <array>

namespace dtf::render {

class GpuFibreSet {
public:
  static constexpr int kMaxLobes = 3;
  GpuFibreSet() = default;
  // Uploads the first min(K, 3) fibres of every voxel (the strongest; more are not rendered), dropping those
  // below relativeThreshold x the voxel's strongest, and `fa` (same grid, component 0) when given. Throws
  // GlError when the grid exceeds GL_MAX_3D_TEXTURE_SIZE, on GPU out-of-memory, or when fa is on another
  // grid.
  void upload(const FibreSet& set, const ScalarVolume* fa = nullptr, float relativeThreshold = 0.0f);
  void clear();
  // Binds the lobe textures to `lobeUnits` and FA to `faUnit` (a program's UNIT_LOBE0..2 and UNIT_FIBRE_FA);
  // unused slots get lobe 0.
  void bind(const std::array<GLuint, kMaxLobes>& lobeUnits, GLuint faUnit) const;
  const glm::mat4& worldToTex() const { return worldToTex_; }
  int lobes() const { return lobes_; }
  bool empty() const { return lobes_ == 0; }

private:
  Texture lobe_[kMaxLobes];
  Texture fa_;
  int lobes_ = 0;
  glm::mat4 worldToTex_{1.0f};
};

} // namespace dtf::render
