// Silhouettes (paper §2.4, Eq. 10): the 3x3 Laplacian of the linear depth (.b of the projection's surface
// target, mm from the eye), thresholded. Pixels without a surface (depth 0) count as depth `background`, so
// the outline of the surface is found too, and get 1 as well: "do not sample here" for the advection.

vec4 silhouetteOrBackground(vec4 d, float background) { return mix(d, vec4(background), lessThanEqual(d, vec4(0.0))); }

// 1 on a silhouette or off the surface, else 0, at the pixel whose lower-left corner is `corner`.
float silhouetteEdge(sampler2D surface, vec2 corner, float threshold, float background) {
  // Two gathers of the depth component give the pixel and its four neighbours (clamped at the edges):
  // at the corner (x, y + 1): (x-1, y+1), (x, y+1), (x, y), (x-1, y); at (x + 1, y): (x, y), (x+1, y),
  // (x+1, y-1), (x, y-1).
  vec2 inv = 1.0 / vec2(textureSize(surface, 0));
  vec4 a = silhouetteOrBackground(textureGather(surface, (corner + vec2(0.0, 1.0)) * inv, 2), background);
  vec4 b = silhouetteOrBackground(textureGather(surface, (corner + vec2(1.0, 0.0)) * inv, 2), background);
  float lap = a.y + a.w + b.y + b.w - 4.0 * a.z;
  return a.z == background || abs(lap) > threshold ? 1.0 : 0.0;
}
