// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/gpu_fibres.h"

#include "render/detail/volume_upload.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dtf::render {

using detail::blurredMask;
using detail::checkFits3D;
using detail::checkUploaded;
using detail::worldToTexture;

namespace {

// Texel channel .b of `f` (4 floats per voxel): channel .g (1 where a voxel has fibres) as the edge field.
void blurredOccupancy(std::vector<float>& f, const glm::ivec3& d) {
  const std::vector<float> e = blurredMask(f, 4, 1, d);
  for (std::size_t i = 0; i < e.size(); ++i)
    f[i * 4 + 2] = e[i];
}

} // namespace

void GpuFibreSet::clear() {
  for (Texture& t : lobe_)
    t = Texture();
  for (Texture& t : lobeB_)
    t = Texture();
  fa_ = Texture();
  lobes_ = 0;
}

void GpuFibreSet::upload(const FibreSet& set, const ScalarVolume* fa, float relativeThreshold) {
  const glm::ivec3 d = set.grid.dims;
  checkFits3D(d, "the fibre set's");
  if (fa && fa->grid.dims != d) throw GlError("the FA volume paired with the fibre set is on another grid");
  const std::size_t n = set.grid.voxelCount();
  const auto k = static_cast<std::size_t>(set.maxFibres);
  if (set.fibres.size() != n * k) throw GlError("fibre set size does not match its grid");
  clear();
  // Slots that follow bundles from voxel to voxel: one advection field per slot.
  const FibreSet slotted = continuousSlots(set, relativeThreshold);
  lobes_ = slotted.maxFibres;
  // Per slot the amplitude-weighted dyadic a d d^T, interpolated per component by the hardware: it does not
  // depend on the sign of d, so seams of the slots' sign alignment (where voxels disagree) interpolate as
  // tensors do, without a voxel-shaped jump.
  std::vector<float> texel(n * 4), texelB(n * 4);
  for (int l = 0; l < lobes_; ++l) {
    for (std::size_t v = 0; v < n; ++v) {
      const Fibre& f = slotted.fibres[v * static_cast<std::size_t>(lobes_) + static_cast<std::size_t>(l)];
      const float a = f.amplitude > 0.0f ? f.amplitude : 0.0f;
      const glm::vec3 e = f.direction;
      texel[v * 4 + 0] = a * e.x * e.x;
      texel[v * 4 + 1] = a * e.x * e.y;
      texel[v * 4 + 2] = a * e.x * e.z;
      texel[v * 4 + 3] = a * e.y * e.y;
      texelB[v * 4 + 0] = a * e.y * e.z;
      texelB[v * 4 + 1] = a * e.z * e.z;
      texelB[v * 4 + 2] = a;
      texelB[v * 4 + 3] = 0.0f;
    }
    lobe_[l] = Texture::create3D(GL_RGBA32F, d.x, d.y, d.z);
    glTextureSubImage3D(lobe_[l].id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RGBA, GL_FLOAT, texel.data());
    lobeB_[l] = Texture::create3D(GL_RGBA32F, d.x, d.y, d.z);
    glTextureSubImage3D(lobeB_[l].id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RGBA, GL_FLOAT, texelB.data());
  }
  // FA (or 1) and occupancy, both zero where the voxel has no fibre: FA / occupancy after interpolation; the
  // occupancy blurred along each axis by [1 2 1] / 4, whose 0.5 contour is the data's smooth edge (as the
  // tensor field's edge texture).
  std::vector<float> f(n * 4, 0.0f);
  for (std::size_t v = 0; v < n; ++v) {
    bool any = false;
    for (int l = 0; l < lobes_; ++l)
      any =
          any ||
          slotted.fibres[v * static_cast<std::size_t>(lobes_) + static_cast<std::size_t>(l)].amplitude > 0.0f;
    if (!any) continue;
    float x = 1.0f;
    if (fa) {
      x = fa->data[v * static_cast<std::size_t>(fa->components)];
      x = std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f;
    }
    f[v * 4] = x;
    f[v * 4 + 1] = 1.0f;
  }
  blurredOccupancy(f, d);
  fa_ = Texture::create3D(GL_RGBA32F, d.x, d.y, d.z);
  glTextureSubImage3D(fa_.id(), 0, 0, 0, 0, d.x, d.y, d.z, GL_RGBA, GL_FLOAT, f.data());
  try {
    checkUploaded(d, n * (static_cast<std::size_t>(lobes_) * 8 + 4) * sizeof(float), "fibre set's");
  } catch (const GlError&) {
    clear();
    throw;
  }
  worldToTex_ = worldToTexture(set.grid);
}

void GpuFibreSet::bind(const std::array<GLuint, kMaxLobes>& lobeUnits,
                       const std::array<GLuint, kMaxLobes>& lobeUnitsB, GLuint faUnit) const {
  for (int l = 0; l < kMaxLobes; ++l) {
    const auto i = static_cast<std::size_t>(l);
    glBindTextureUnit(lobeUnits[i], l < lobes_ ? lobe_[l].id() : lobe_[0].id());
    glBindTextureUnit(lobeUnitsB[i], l < lobes_ ? lobeB_[l].id() : lobeB_[0].id());
  }
  glBindTextureUnit(faUnit, fa_.id());
}

} // namespace dtf::render
