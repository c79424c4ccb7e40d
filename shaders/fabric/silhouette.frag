#version 450 core
// Silhouette pass (paper §2.4, Eq. 10; common/silhouette.glsl): e in {0, 1}, 1 on silhouettes and off the
// surface, so the advection finds "do not sample here" with a single fetch. A frame that restarts the
// advection computes the same edges in its restart pass instead (fabric/advection.frag, RESET SILHOUETTES).
#include "common/silhouette.glsl"
#ifdef FAR_PLANE
layout(early_fragment_tests) in; // only covered pixels are shaded
#endif
layout(binding = UNIT_SURFACE) uniform sampler2D u_surface; // .b linear depth (0 = no surface)

flat in vec2 v_silhouette; // threshold, background: the uniforms of fabric/silhouette.vert

out float o_edge;

void main() { o_edge = silhouetteEdge(u_surface, floor(gl_FragCoord.xy), v_silhouette.x, v_silhouette.y); }
