// GPU copy of a FibreSet for the multi-population fabric: up to three RGBA32F 3D textures, one per fibre
// slot of continuousSlots(set) (a slot follows one bundle from voxel to voxel; unit world direction xyz,
// amplitude; 0 = absent; nearest filtering: the projection pass gathers the
// 8 voxels around a point and matches their lobes itself, see shaders/common/fibre_field.glsl), and an R32F
// FA texture (linear) from a paired tensor, or 1 everywhere without one. Uploaded once per change of the
// data, never per frame.
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/volume.h"
#include "render/gl_objects.h"

#include <glm/glm.hpp>

namespace dtf::render {

class GpuFibreSet {
public:
  static constexpr int kMaxLobes = 3;
  GpuFibreSet() = default;
  // Uploads the first min(K, 3) fibres of every voxel (the strongest; more are not rendered) and `fa` (same
  // grid, component 0) when given. Throws GlError when the grid exceeds GL_MAX_3D_TEXTURE_SIZE, on GPU
  // out-of-memory, or when fa is on another grid.
  void upload(const FibreSet& set, const ScalarVolume* fa = nullptr);
  void clear();
  // Binds the lobe textures to units 0, 1, 5 and FA to unit 6 (the bindings of fibre_field.glsl).
  void bind() const;
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
