#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The composite's vertex shader (fabric/composite.frag): the fullscreen triangle, and the pass's parameters
// handed on as flat outputs, read here three times a draw (on llvmpipe a fragment shader pays for each read
// of a uniform component on every block of pixels, about four times what a flat input costs).
#include "common/fullscreen_triangle.glsl"
#ifdef ADVECT
#include "common/iteration_params.glsl" // the frame's last iteration runs in the same pass
#endif

uniform ivec2 u_guard;        // offset of the viewport inside the guarded targets
uniform ivec2 u_origin = ivec2(0); // the viewport's lower-left pixel in the framebuffer drawn into
uniform vec2 u_scale = vec2(1.0); // internal / viewport resolution (nearest upsampling when < 1)
uniform ivec2 u_target;       // the guarded targets' size
uniform float u_r = 0.5;      // blend between the two directions (Eq. 13)
uniform float u_contrast = 1.0; // f(p) = clamp(0.5 + contrast (p - 0.5)); 1 = Eq. 13 on the raw fields
uniform float u_lightWeight = 0.5; // engineering: light(L) = weight * L
uniform float u_lightMix = 0.8;    // medical: intensity factor mix(1, L, lightMix)
uniform bool u_lighting = true;
uniform float u_depthColour = 0.5; // DEPTH_COLOUR: 0..1 blend of far surfaces towards a cool grey
uniform vec2 u_depthRange;         // linear depth of the nearest and farthest scene points (mm)
uniform vec4 u_eyeDepth;           // projection terms of eye z: clip z = x z + y, clip w = z z + w
uniform float u_sharpen = 0.5;     // SHARPEN: unsharp mask weight on the composed colour
uniform float u_secondaryRatio = 0.5; // medical: lambda2'/lambda1' above which the secondary appears
uniform float u_secondaryFa = 0.2;    // medical: FA below which the secondary appears
uniform float u_fadeOutOfPlane = 0.0; // FADE: 0..1 fade where |e1.n| is large
uniform vec2 u_opacityFa = vec2(0.15, 0.4); // anatomy: FA at which the fabric starts to show, and is opaque
uniform vec3 u_clearColour = vec3(0.0); // OVER_CLEAR: the colour the framebuffer holds where the pass draws

flat out ivec4 v_place;  // guard, origin
flat out ivec2 v_target;
flat out vec2 v_scale;
flat out vec4 v_colourA; // r, contrast, light weight, light mix
flat out vec4 v_colourB; // lighting (1 or 0), secondary ratio, secondary FA, fade out of plane
flat out vec4 v_colourC; // opacity FA (low, high), depth colour, sharpen
flat out vec2 v_depthRange;
flat out vec4 v_eyeDepth;
flat out vec3 v_clearColour;

void main() {
  fullscreenTriangle();
#ifdef ADVECT
  handOnIteration();
#endif
  v_place = ivec4(u_guard, u_origin);
  v_target = u_target;
  v_scale = u_scale;
  v_colourA = vec4(u_r, u_contrast, u_lightWeight, u_lightMix);
  v_colourB = vec4(u_lighting ? 1.0 : 0.0, u_secondaryRatio, u_secondaryFa, u_fadeOutOfPlane);
  v_colourC = vec4(u_opacityFa, u_depthColour, u_sharpen);
  v_depthRange = u_depthRange;
  v_eyeDepth = u_eyeDepth;
  v_clearColour = u_clearColour;
}
