#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Silhouette pass (paper §2.4, Eq. 10; common/silhouette.glsl): e in {0, 1}, 1 on silhouettes and off the
// surface, so the advection finds "do not sample here" with a single fetch. A frame that restarts the
// advection computes the same edges in its restart pass instead (fabric/advection.frag, RESET SILHOUETTES).
layout(binding = IMAGE_SURFACE, rgba32f) uniform readonly image2D u_surfaceImage; // .b linear depth (0: none)
#include "common/silhouette.glsl"
#ifdef FAR_PLANE
layout(early_fragment_tests) in; // only covered pixels are shaded
#endif

flat in vec2 v_silhouette;   // threshold, background: the uniforms of fabric/silhouette.vert
flat in ivec2 v_surfaceLast; // the surface target's last pixel

out float o_edge;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  o_edge = silhouetteEdge(p, v_surfaceLast, imageLoad(u_surfaceImage, p).b, v_silhouette.x, v_silhouette.y);
}
