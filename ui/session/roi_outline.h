// SPDX-License-Identifier: GPL-3.0-or-later
// How the viewer draws the regions of the ROI selection (ui/session/roi_selection.h): a colour per kind, and
// where a region cuts a slice plane (a circle for a sphere, a polygon for a box), in world RAS mm, for the
// outlines of the ortho layout's slice panes and the tests that check them. Pure geometry, no GL.
#pragma once

#include "surfaces/selection/regions.h"

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>
#include <vector>

namespace dtf::session {

// Include green, exclude red, ordered include blue (RGB in 0..255); the Tracts panel names them.
glm::u8vec3 regionKindColour(surfaces::RegionKind kind);
const char* regionKindColourName(surfaces::RegionKind kind); // "green", "red", "blue"

// The outline of `region` on the plane through `point` with unit normal `normal`, as a closed polygon of
// world points in `out` (cleared first; its capacity is reused): a sphere's circle in `segments` points, a
// box's section (3 to 6 corners, in order around it). False, with `out` empty, when the region does not cut
// the plane or is a mask (maskOutline draws those).
// Corner i (0..7) of a box region: bit 0 picks hi.x over lo.x, bit 1 hi.y, bit 2 hi.z. kBoxFaces lists the
// six faces as corner indices in order around each, for drawing a box's faces and edges.
inline glm::dvec3 boxCorner(const glm::dvec3& lo, const glm::dvec3& hi, int i) {
  return {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
}
inline glm::dvec3 boxCorner(const surfaces::Region& box, int i) { return boxCorner(box.lo, box.hi, i); }
inline constexpr int kBoxFaces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                        {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};

bool regionOutline(const surfaces::Region& region, const glm::dvec3& point, const glm::dvec3& normal,
                   std::vector<glm::dvec3>& out, int segments = 64);

// Lattice points per side maskOutline samples at most.
inline constexpr int kMaskOutlineSamples = 512;
// The outline of a mask region on the same plane: the plane is sampled on a square lattice (spacing half the
// mask's smallest voxel size, coarser where the mask's extent needs more than kMaskOutlineSamples per side)
// with the region's own rule (nearest voxel non-zero), and every pair of neighbouring samples of which one
// is inside gives the lattice edge between them: `out` holds these as segments, pairs of world points
// (cleared first; `out` and `scratch` keep their capacity). A staircase at half a voxel: display only. False,
// with `out` empty, when the region is not a mask or no sample on the plane is inside.
bool maskOutline(const surfaces::Region& region, const glm::dvec3& point, const glm::dvec3& normal,
                 std::vector<glm::dvec3>& out, std::vector<unsigned char>& scratch);

// Boundary faces of a mask region drawn in 3D at most: past it the viewer draws the mask's bounds as a box.
inline constexpr std::size_t kMaskFaceCap = 20000;
// A mask region in 3D: the surface of its voxels' cells (the region's own rule: the nearest voxel non-zero),
// in world RAS mm.
struct MaskSurface {
  std::vector<glm::dvec3> faces;   // 4 corners per face, in order around it: each face between a cell
                                   // inside and a cell outside (zero, or beyond the grid)
  std::vector<glm::dvec3> creases; // segments (pairs of points): the cell edges where faces of different
                                   // orientations meet, the outline of the staircase
  glm::dvec3 lo{0.0}, hi{0.0};     // world bounds of the cells inside (surfaces::Region::bounds)
  bool drawn = false;              // faces and creases hold the surface (at most maxFaces faces)
};
// False, with an empty surface, when the region is not a mask or holds no voxel; `drawn` false when the
// surface has more than maxFaces faces (bounds only).
bool maskSurface(const surfaces::Region& region, MaskSurface& out, std::size_t maxFaces = kMaskFaceCap);

} // namespace dtf::session
