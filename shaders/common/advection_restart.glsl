// SPDX-License-Identifier: GPL-3.0-or-later
// The restart of the advection (RESET of fabric/advection.frag, and of its compute twin fabric/advection.comp):
// p_0 = beta on covered pixels, BLOCKED on silhouettes, off the surface and on the target's outer ring;
// see fabric/advection.frag.
#include "common/texel.glsl"
// The surface target: .r beta, .b linear depth, .a coverage.
layout(binding = IMAGE_SURFACE, rgba32f) uniform readonly image2D u_surfaceImage;
#ifdef COMPUTE
layout(binding = UNIT_SURFACE) uniform sampler2D u_surface; // the same target: its size
ivec2 surfaceLast() { return textureSize(u_surface, 0) - 1; }
#else
flat in ivec2 v_surfaceLast; // the surface target's last pixel, from fabric/advection.vert
ivec2 surfaceLast() { return v_surfaceLast; }
#endif
layout(binding = UNIT_SILHOUETTE) uniform sampler2D u_silhouette; // RESET: .r 1 on silhouettes and off the surface
#ifdef REPROJECT
layout(binding = UNIT_HISTORY_SURFACE) uniform sampler2D u_histSurface; // previous frame's surface (.b depth)
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth;                // this frame's window depth
// u_windowToWorld, u_worldToPrevWindow, u_worldToPrevEye, u_depthTol: the uniforms of fabric/advection.vert
// (described there), received as its flat outputs (the fragment pass only: REPROJECT has no compute twin).
flat in mat4 v_windowToWorld;
flat in mat4 v_worldToPrevWindow;
flat in mat4 v_worldToPrevEye;
flat in float v_depthTol;
#define u_windowToWorld v_windowToWorld
#define u_worldToPrevWindow v_worldToPrevWindow
#define u_worldToPrevEye v_worldToPrevEye
#define u_depthTol v_depthTol
#endif

#ifdef RESET
#ifdef SILHOUETTES
// The restart of a frame whose projection changed finds the silhouettes itself (the silhouette pass's test,
// common/silhouette.glsl) and writes them for the composite and later frames: one fullscreen pass fewer.
#include "common/silhouette.glsl"
#ifdef COMPUTE
uniform float u_threshold;  // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background; // linear depth assigned to empty pixels
#else // the same uniforms of fabric/advection.vert, as its flat output
flat in vec2 v_silhouette;
#define u_threshold (v_silhouette.x)
#define u_background (v_silhouette.y)
#endif
#endif
#endif

// p_0 at pixel p (p1, p2, p3 = beta, or BLOCKED) and, with SILHOUETTES, the silhouette found there.
void restartPixel(ivec2 p, out vec3 state, out float edge) {
  vec2 fragCoord = vec2(p) + 0.5;
  vec4 s = imageLoad(u_surfaceImage, p);
  ivec2 last = surfaceLast();
  bool ring = p.x == 0 || p.y == 0 || p.x == last.x || p.y == last.y;
#ifdef SILHOUETTES
  edge = silhouetteEdge(p, last, s.b, u_threshold, u_background);
  bool blocked = s.a < 0.5 || ring || edge > 0.5;
#else
  edge = 0.0;
  bool blocked = s.a < 0.5 || ring || texel(u_silhouette, p).r > 0.5;
#endif
  float p1 = s.r, p2 = complementSecond() ? 1.0 - s.r : s.r;
#ifdef REPROJECT
  if (!blocked) {
    vec4 w = u_windowToWorld * vec4(fragCoord, texel(u_depth, p).r, 1.0);
    w /= w.w;
    vec4 q = u_worldToPrevWindow * w;
    vec2 x = q.xy / q.w;
    if (all(greaterThanEqual(x, vec2(1.0))) && all(lessThan(x, vec2(last)))) {
      vec4 h = texel(u_histSurface, ivec2(x));
      if (h.a > 0.5 && abs(h.b + (u_worldToPrevEye * w).z) < u_depthTol) {
        vec2 uv = x / vec2(last + 1);
        float a = texture(u_prev1, uv).r, b = texture(u_prev2, uv).r;
        if (a >= 0.0 && b >= 0.0) {
          p1 = a;
          p2 = b;
        }
      }
    }
  }
#endif
  state = blocked ? vec3(BLOCKED) : vec3(p1, p2, s.r);
}
