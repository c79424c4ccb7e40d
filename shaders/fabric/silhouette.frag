#version 450 core
// Silhouette pass (paper §2.4, Eq. 10): 3x3 Laplacian of the LINEAR depth (mm from the eye, written by
// the projection pass), thresholded. Pixels without geometry count as depth u_background so the outline
// of the surface is found too. Output e in {0, 1}; empty pixels get 1 as well, so the advection pass
// finds "do not sample here" (silhouette or off the surface) with a single fetch.
#ifdef FAR_PLANE
layout(early_fragment_tests) in; // only covered pixels are shaded
#endif
layout(binding = 0) uniform sampler2D u_surface; // .b linear depth, .a coverage

uniform float u_threshold;   // mm of |Laplacian| above which a pixel is a silhouette
uniform float u_background;  // linear depth assigned to empty pixels (beyond the far side of the scene)

out float o_edge;

float depthAt(ivec2 p) {
  vec4 s = texelFetch(u_surface, clamp(p, ivec2(0), textureSize(u_surface, 0) - 1), 0);
  return s.a > 0.5 ? s.b : u_background;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(u_surface, p, 0);
  if (s.a < 0.5) {
    o_edge = 1.0;
    return;
  }
  float lap = depthAt(p + ivec2(1, 0)) + depthAt(p - ivec2(1, 0)) + depthAt(p + ivec2(0, 1)) +
              depthAt(p - ivec2(0, 1)) - 4.0 * s.b;
  o_edge = abs(lap) > u_threshold ? 1.0 : 0.0;
}
