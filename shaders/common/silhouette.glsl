// SPDX-License-Identifier: GPL-3.0-or-later
// Silhouettes (paper §2.4, Eq. 10): the 3x3 Laplacian of the linear depth (.b of the projection's surface
// target, mm from the eye), thresholded. Pixels without a surface (depth 0) count as depth `background`, so
// the outline of the surface is found too, and get 1 as well: "do not sample here" for the advection.

// The including shader declares u_surfaceImage, the surface target as an rgba32f image: single texels as
// image loads, which llvmpipe inlines (a gather calls a generated function).

vec4 silhouetteOrBackground(vec4 d, float background) { return mix(d, vec4(background), lessThanEqual(d, vec4(0.0))); }

// 1 on a silhouette or off the surface, else 0, at pixel p of linear depth `depth`, from its four neighbours;
// `last`: the target's last pixel (beyond the edge the edge pixel repeats).
float silhouetteEdge(ivec2 p, ivec2 last, float depth, float threshold, float background) {
  vec4 n = vec4(imageLoad(u_surfaceImage, ivec2(p.x, min(p.y + 1, last.y))).b,  // up
                imageLoad(u_surfaceImage, ivec2(max(p.x - 1, 0), p.y)).b,       // left
                imageLoad(u_surfaceImage, ivec2(min(p.x + 1, last.x), p.y)).b,  // right
                imageLoad(u_surfaceImage, ivec2(p.x, max(p.y - 1, 0))).b);      // down
  n = silhouetteOrBackground(n, background);
  float c = depth <= 0.0 ? background : depth;
  float lap = n.x + n.y + n.z + n.w - 4.0 * c;
  return c == background || abs(lap) > threshold ? 1.0 : 0.0;
}
