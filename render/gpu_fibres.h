// SPDX-License-Identifier: GPL-3.0-or-later
// GPU copy of a FibreSet for the multi-population fabric: continuousSlots of the set (lobes below the
// relative threshold dropped, the rest matched between neighbouring voxels) as two RGBA32F 3D textures per
// slot (the amplitude-weighted dyadic a d d^T: a (xx, xy, xz, yy) and a (yz, zz), a; trilinear, 0 outside),
// and an RGBA32F texture (FA of a paired tensor or 1, 1 where the voxel has fibres, that blurred). See
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
  // Binds each slot's two lobe textures to `lobeUnits` and `lobeUnitsB` and FA to `faUnit` (a program's
  // UNIT_LOBE0..2, UNIT_LOBE0B..2B and UNIT_FIBRE_FA); unused slots get lobe 0.
  void bind(const std::array<GLuint, kMaxLobes>& lobeUnits, const std::array<GLuint, kMaxLobes>& lobeUnitsB,
            GLuint faUnit) const;
  const glm::mat4& worldToTex() const { return worldToTex_; }
  int lobes() const { return lobes_; }
  bool empty() const { return lobes_ == 0; }

private:
  Texture lobe_[kMaxLobes];  // a (xx, xy, xz, yy)
  Texture lobeB_[kMaxLobes]; // a (yz, zz), a, 0
  Texture fa_;
  int lobes_ = 0;
  glm::mat4 worldToTex_{1.0f};
};

} // namespace dtf::render
