#version 450 core
// Silhouette pass (paper §2.4, Eq. 10): 3x3 Laplacian of the LINEAR depth (mm from the eye, written by
// the projection pass), thresholded. Pixels without geometry count as depth u_background so the outline
// of the surface is found too. Output e in {0, 1}; empty pixels get 1 as well, so the advection pass
// finds "do not sample here" (silhouette or off the surface) with a single fetch.
#ifdef FAR_PLANE
layout(early_fragment_tests) in; // only covered pixels are shaded
#endif
layout(binding = UNIT_SURFACE) uniform sampler2D u_surface; // .b linear depth (0 = no surface)

uniform float u_threshold;   // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background;  // linear depth assigned to empty pixels (beyond the far side of the scene)

out float o_edge;

// Linear depth, or u_background where there is no surface (the surface target is cleared to 0 and covered
// pixels have depth > 0).
vec4 orBackground(vec4 d) { return mix(d, vec4(u_background), lessThanEqual(d, vec4(0.0))); }

void main() {
  // Two gathers of the depth component give the pixel and its four neighbours (clamped at the edges):
  // at the corner (x, y + 1): (x-1, y+1), (x, y+1), (x, y), (x-1, y); at (x + 1, y): (x, y), (x+1, y),
  // (x+1, y-1), (x, y-1).
  vec2 inv = 1.0 / vec2(textureSize(u_surface, 0));
  vec2 c = floor(gl_FragCoord.xy);
  vec4 a = orBackground(textureGather(u_surface, (c + vec2(0.0, 1.0)) * inv, 2));
  vec4 b = orBackground(textureGather(u_surface, (c + vec2(1.0, 0.0)) * inv, 2));
  float lap = a.y + a.w + b.y + b.w - 4.0 * a.z;
  // Off the surface: 1, so the advection finds "do not sample here" with a single fetch.
  o_edge = a.z == u_background || abs(lap) > u_threshold ? 1.0 : 0.0;
}
