// SPDX-License-Identifier: GPL-3.0-or-later
// What every fabric pass needs to know about the current view: matrices of the guarded target (the
// viewport plus a border of `guard` pixels on each side, so advected threads do not fray at the screen
// edge), sizes, the pixel size in mm and the depth range of the scene.
#pragma once

#include "render/camera.h"

#include <glm/glm.hpp>

namespace dtf::render {

struct FrameView {
  glm::ivec2 viewport{0};   // output size in pixels
  glm::ivec2 internal{0};   // size the fabric is computed at (viewport * scale)
  float scale = 1.0f;       // internal / viewport resolution (< 1: lower resolution while moving)
  int guard = 0;            // border added on each side of the internal targets
  glm::ivec2 target{0};     // internal + 2 guard
  glm::mat4 view{1.0f};     // world -> eye
  glm::mat4 viewProj{1.0f}; // world -> clip of the guarded target
  glm::mat4 viewProjViewport{1.0f}; // world -> clip of the viewport alone
  glm::mat3 viewRot{1.0f};  // world -> eye rotation
  glm::mat4 eyeToWorld{1.0f}; // inverse of view
  glm::mat4 clipToEye{1.0f};  // inverse projection of the guarded target
  glm::vec4 eyeDepth{0.0f, 0.0f, 0.0f, 1.0f}; // clip z = x ze + y, clip w = z ze + w for eye z ze
  bool orthographic = true;
  float pixelMm = 1.0f;     // size of one pixel at the target distance, mm
  float pixelMmPerDepth = 0.0f; // perspective: pixel size in mm per mm of eye depth
  glm::vec2 depthRange{0.0f, 1.0f}; // linear eye depth of the scene bounds, mm
  bool boundsInFront = false; // every corner of the scene bounds lies beyond the near plane
  // The viewport pixels (x, y, width, height from the lower left) the scene bounds can cover: their eight
  // corners' projection with a margin for rounding and the nearest upsampling of a lower internal
  // resolution; the whole viewport unless the bounds lie in front of the near plane. The composite shades
  // only these (a software rasteriser runs a fragment shader's every instruction even where it discards).
  // A negative width: not known, the whole viewport.
  glm::ivec4 coverRect{0, 0, -1, -1};
  // The same in the pixels of the guarded internal targets (2 pixels margin): the restarts of the advection
  // shade only these and clear the rest (a negative width: the whole target).
  glm::ivec4 targetCoverRect{0, 0, -1, -1};

  // Builds the view of `camera` for a viewport, with the scene bounds [lo, hi] for the depth range;
  // the fabric targets are computed at `scale` times the viewport resolution.
  static FrameView make(const Camera& camera, glm::ivec2 viewport, int guard, const glm::vec3& lo,
                        const glm::vec3& hi, float scale = 1.0f);
  // The view of a host's matrices: `view` world -> eye (rotation and translation), `projection` eye -> clip
  // (GL conventions, perspective or orthographic) for a viewport of `viewport` pixels, full resolution. The
  // scene bounds [lo, hi] give the depth range; a perspective view's pixelMm is taken at the eye depth of
  // `reference` (world mm; the renderer's camera target plays this part in make()).
  static FrameView fromHost(const glm::mat4& view, const glm::mat4& projection, glm::ivec2 viewport, int guard,
                            const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& reference);
};

} // namespace dtf::render
