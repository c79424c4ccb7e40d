// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/frame_view.h"

#include <algorithm>
#include <cmath>

namespace dtf::render {

namespace {

// Sets f.depthRange to the eye depths the bounds box [lo, hi] spans (clamped to the front of the eye) and
// returns the nearest (unclamped).
float boundsDepthRange(FrameView& f, const glm::vec3& lo, const glm::vec3& hi) {
  float dmin = 1e30f, dmax = -1e30f;
  for (int i = 0; i < 8; ++i) {
    glm::vec3 p((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    float d = -(f.view * glm::vec4(p, 1.0f)).z;
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  f.depthRange = {std::max(dmin, 0.0f), std::max(dmax, dmin + 1e-3f)};
  return dmin;
}

// The pixels of an image of `size` pixels under worldToClip that the bounds box [lo, hi] can cover (see
// FrameView::coverRect), with `margin` pixels around; the whole image unless every corner is in front.
glm::ivec4 boundsRect(const glm::mat4& worldToClip, glm::ivec2 size, bool inFront, const glm::vec3& lo,
                      const glm::vec3& hi, float margin) {
  const glm::ivec4 whole(0, 0, size.x, size.y);
  if (!inFront) return whole;
  glm::vec2 a(1e30f), b(-1e30f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::vec4 c = worldToClip * glm::vec4(corner, 1.0f);
    if (!(c.w > 0.0f)) return whole;
    glm::vec2 px = (glm::vec2(c) / c.w * 0.5f + 0.5f) * glm::vec2(size);
    a = glm::min(a, px);
    b = glm::max(b, px);
  }
  const glm::vec2 far(1e7f); // also false for NaN
  if (!(glm::all(glm::lessThan(glm::abs(a), far)) && glm::all(glm::lessThan(glm::abs(b), far)))) return whole;
  const glm::ivec2 p0 = glm::clamp(glm::ivec2(glm::floor(a - margin)), glm::ivec2(0), size);
  const glm::ivec2 p1 = glm::clamp(glm::ivec2(glm::ceil(b + margin)), glm::ivec2(0), size);
  return {p0.x, p0.y, p1.x - p0.x, p1.y - p0.y};
}

} // namespace

FrameView FrameView::make(const Camera& camera, glm::ivec2 viewport, int guard, const glm::vec3& lo,
                          const glm::vec3& hi, float scale) {
  FrameView f;
  f.viewport = viewport;
  f.scale = std::clamp(scale, 0.1f, 1.0f);
  f.internal = glm::max(glm::ivec2(glm::round(glm::vec2(viewport) * f.scale)), glm::ivec2(1));
  f.guard = guard;
  f.target = f.internal + 2 * guard;
  const double aspect = double(viewport.x) / std::max(viewport.y, 1);
  glm::dmat4 view = camera.view();
  glm::dmat4 proj = camera.projection(aspect);
  // The guarded target sees more of the scene at the same pixel scale: shrink NDC by viewport/target.
  glm::dmat4 shrink(1.0);
  shrink[0][0] = double(f.internal.x) / f.target.x;
  shrink[1][1] = double(f.internal.y) / f.target.y;
  f.view = glm::mat4(view);
  f.viewProj = glm::mat4(shrink * proj * view);
  f.viewProjViewport = glm::mat4(proj * view);
  f.viewRot = glm::mat3(view);
  f.eyeToWorld = glm::mat4(glm::inverse(view));
  f.clipToEye = glm::mat4(glm::inverse(shrink * proj));
  f.eyeDepth = glm::vec4(proj[2][2], proj[3][2], proj[2][3], proj[3][3]);
  f.orthographic = camera.orthographic;
  double dist = glm::length(camera.target - camera.eye);
  double halfH = camera.orthographic ? camera.orthoHalfHeight
                                     : dist * std::tan(0.5 * glm::radians(camera.fovYDeg));
  // Sizes of one internal pixel.
  f.pixelMm = static_cast<float>(2.0 * halfH / std::max(f.internal.y, 1));
  f.pixelMmPerDepth = static_cast<float>(2.0 * std::tan(0.5 * glm::radians(camera.fovYDeg)) / std::max(f.internal.y, 1));
  const float dmin = boundsDepthRange(f, lo, hi);
  f.boundsInFront = dmin > camera.nearPlane;
  // Two pixels for rounding; in the viewport also the span of one internal pixel (the composite shows an
  // internal texel, whose centre the rasteriser covered, over every viewport pixel mapped to it).
  const float upsampling = std::ceil(1.0f / f.scale);
  f.coverRect = boundsRect(f.viewProjViewport, f.viewport, f.boundsInFront, lo, hi, 2.0f + upsampling);
  f.targetCoverRect = boundsRect(f.viewProj, f.target, f.boundsInFront, lo, hi, 2.0f);
  return f;
}

FrameView FrameView::fromHost(const glm::mat4& view, const glm::mat4& projection, glm::ivec2 viewport, int guard,
                              const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& reference) {
  FrameView f;
  f.viewport = glm::max(viewport, glm::ivec2(1));
  f.scale = 1.0f;
  f.internal = f.viewport;
  f.guard = guard;
  f.target = f.internal + 2 * guard;
  const glm::dmat4 v(view), proj(projection);
  glm::dmat4 shrink(1.0);
  shrink[0][0] = double(f.internal.x) / f.target.x;
  shrink[1][1] = double(f.internal.y) / f.target.y;
  f.view = view;
  f.viewProj = glm::mat4(shrink * proj * v);
  f.viewProjViewport = glm::mat4(proj * v);
  f.viewRot = glm::mat3(view);
  f.eyeToWorld = glm::mat4(glm::inverse(v));
  f.clipToEye = glm::mat4(glm::inverse(shrink * proj));
  f.eyeDepth = glm::vec4(proj[2][2], proj[3][2], proj[2][3], proj[3][3]);
  // Clip w does not depend on eye z for an orthographic projection.
  f.orthographic = proj[2][3] == 0.0;
  // One pixel spans 2 / (P[1][1] h) in eye units, times the depth for a perspective projection.
  const double perPixel = 2.0 / (std::abs(proj[1][1]) * std::max(f.internal.y, 1));
  const double refDepth = std::max(-(v * glm::dvec4(glm::dvec3(reference), 1.0)).z, 1e-6);
  f.pixelMm = static_cast<float>(f.orthographic ? perPixel : perPixel * refDepth);
  f.pixelMmPerDepth = f.orthographic ? 0.0f : static_cast<float>(perPixel);
  boundsDepthRange(f, lo, hi);
  f.boundsInFront = false; // no mesh to cull on this route
  return f;
}

} // namespace dtf::render
