// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to dtf_render: the checks and the texture-coordinate map shared by the 3D-texture uploads of
// tensor fields, scalar volumes and fibre sets (render/gpu_scene.cpp, render/gpu_fibres.cpp).
#pragma once

#include "io/model/grid.h"

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace dtf::render::detail {

// Throws GlError naming `what` when a grid of dims d does not fit GL_MAX_3D_TEXTURE_SIZE.
void checkFits3D(const glm::ivec3& d, const char* what);
// After the 3D textures of `what` were allocated and filled: GL_OUT_OF_MEMORY (or another GL error) becomes
// a GlError that says which data did not fit, instead of a later failure with textures that hold nothing.
void checkUploaded(const glm::ivec3& d, std::size_t bytes, const char* what);
// World RAS mm -> 3D texture coordinates of the grid: tex = (voxel + 0.5) / dims.
glm::mat4 worldToTexture(const Grid& grid);
// The data's edge field: channel `channel` of `texels` (`stride` floats per voxel of a grid of dims d, a 0/1
// mask) blurred along each axis by [1 2 1] / 4, replicated at the grid's faces so that data reaching a face
// stay data up to it. Its 0.5 contour is the smooth outline of tensor fields and fibre sets.
std::vector<float> blurredMask(const std::vector<float>& texels, int stride, int channel, const glm::ivec3& d);

} // namespace dtf::render::detail
