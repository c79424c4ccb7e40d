#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The composite's depth alone, for CompositeDepth::Present: the window depth of the surface on every pixel
// the composite draws (fabric/composite.frag, without WINDOW_DEPTH at full resolution), and nothing where it
// discards: off the surface, and without a background volume where the data's cover is 0. Drawn once per
// projection into a cleared depth target that each frame copies into its own; the composite then shades
// exactly these pixels behind the early depth test, and the frame's depth is the one it would have written.
#include "common/window_depth.glsl"

// Read as images, as the composite reads them (on llvmpipe an image load is inlined).
layout(binding = IMAGE_SURFACE, rgba32f) uniform readonly image2D u_surface; // .b linear depth (mm), .a coverage
layout(binding = IMAGE_LAMBDA, rgba8) uniform readonly image2D u_lambda;     // .w the data's cover

// u_guard (the viewport's offset inside the guarded targets) and u_eyeDepth (projection terms of eye z): the
// uniforms of fabric/composite.vert, received as its flat outputs.
flat in ivec4 v_place;
flat in vec4 v_eyeDepth;
#define u_guard (v_place.xy)
#define u_eyeDepth v_eyeDepth

void main() {
  ivec2 t = ivec2(gl_FragCoord.xy) + u_guard;
  vec4 s = imageLoad(u_surface, t);
  if (s.a < 0.5) discard;
#ifndef BACKGROUND
  if (imageLoad(u_lambda, t).w <= 0.0) discard; // the composite's alpha is the cover: it discards these
#endif
  gl_FragDepth = windowDepth(u_eyeDepth, s.b); // as fabric/composite.frag writes it
}
