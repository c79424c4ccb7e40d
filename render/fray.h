// SPDX-License-Identifier: GPL-3.0-or-later
// CPU side of the uncertainty display (shaders/common/fray.glsl): the per-cell turn of the advection
// directions as a reference for the GLSL, and the legend that says what the look means in degrees.
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/image.h"
#include "render/text.h"

#include <cstdint>
#include <glm/glm.hpp>

namespace dtf::render {

// frayHash of fray.glsl (lowbias32).
std::uint32_t frayHash(std::uint32_t x);
// frayDraw of fray.glsl: the signed unit draw in [-1, 1] of the noise cell holding `world` (mm).
float frayDraw(glm::vec3 world, glm::vec3 origin, float lod, float cells, std::uint32_t salt);
// The turn in radians at `world` for a cone of `coneDeg` degrees and strength `fray`.
float frayAngle(glm::vec3 world, glm::vec3 origin, float lod, float cells, float coneDeg, float fray,
                std::uint32_t salt = 0);

// Per-fibre cones (`cones`: one component per fibre of `set`, fibre index order, degrees) in the slot order
// of `slotted` = continuousSlots(set, ...): 3 components, slot j's cone; slots without a fibre get 0. A
// slot's lobe is matched to the voxel's fibre with the same amplitude and the largest |cos|.
ScalarVolume slotCones(const FibreSet& set, const FibreSet& slotted, const ScalarVolume& cones);

// Draws the legend of the uncertainty display at the image's bottom-left corner: swatches of short
// strokes turned as the renderer turns them for cones of 0, 10, 20 and 40 degrees at strength `fray`,
// with their labels and a caption. `scale` is the legend's size unit (1: 18-pixel swatches, 11-pixel text).
void drawFrayLegend(Image& image, float fray, int scale);
void drawFrayLegend(Canvas& canvas, float fray, int scale);
// The legend's height from the bottom edge in pixels (its margin included).
int frayLegendHeight(int scale);

} // namespace dtf::render
