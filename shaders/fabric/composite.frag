#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Composite pass (paper §2.6, Eq. 13, and §3.2). Engineering mode, with f = contrast-stretched p_k:
//   R = r f(p2) / (8 f(p1)^2) + e + light(L)
//   G = (1 - r) f(p1) / (8 f(p2)^2) + e + light(L)
//   B = e + light(L)
// light(L) adds the same amount to all channels, which changes brightness, not hue. Medical mode:
// the primary fabric as luminance of the DEC colour of the 3D principal eigenvector (x red, y green,
// z blue) modulated by FA; where a secondary in-plane direction exists, it is drawn in grey beneath the
// primary threads. Writes gl_FragDepth, the window depth of the surface computed from its linear depth, so
// other geometry occludes correctly.
// FIBRES (fibre sets): each population's fabric in its own DEC colour (|d| of its world direction, FA
// modulated when a tensor is paired), layered: the weakest population present is the base, each stronger
// one is drawn over it where its threads are bright (strongest on top); a population's weight (amplitude
// relative to the strongest x its in-surface fraction) dims it and thins its cover, so weak and out-of-plane
// populations fade.
// Looks: plain (the paper's: the fabric wherever there is tensor data) and anatomy (ANATOMY: the fabric's
// opacity is smoothstep(u_opacityFa.x, u_opacityFa.y, FA) over the grey beneath, so isotropic tissue shows
// the anatomy and white matter its full colours). The grey beneath is the background volume (BACKGROUND),
// else FA. The data's edge is the projection's cover ramp (lambda.w, 0..1 over about a pixel): outside it the
// background volume shows, or without one the framebuffer beneath (the output alpha is the cover; blended).
// Variants (compile-time: a software rasteriser pays for untaken branches): MEDICAL, SILHOUETTES,
// BACKGROUND (a grey volume beneath the fabric), DEPTH_COLOUR, SHARPEN, FIBRES, WINDOW_DEPTH (the
// depth written is the projection's window depth texel, a host's surface depth, not recomputed), ANATOMY,
// DEC_FA (MEDICAL: no fabric, the DEC-FA map |e1| x FA, for comparison), FADE (MEDICAL: fadeOutOfPlane > 0),
// FAR_PLANE (the framebuffer already holds the surface's depth: the triangle at the far plane is drawn with
// GL_GREATER and the early depth test, so only covered pixels are shaded, and no depth is written),
// OVER_CLEAR (the framebuffer holds u_clearColour with alpha 1 wherever the pass draws, the renderer's
// freshly cleared output: the colour is laid over it here, with blending off; that gives what blending
// would, to within one level of rounding, without reading the framebuffer).
// ADVECT: the frame's last advection iteration and the composite in one pass (one full-screen pass fewer,
// and no loads of the state just computed, nor of the 16-byte surface texel). It is drawn over the guarded state targets, not the viewport:
// the iteration's next state at draw buffers 1, 2 (3: THIRD, the third field) and the colour laid over
// u_clearColour at draw buffer 0, for every pixel the iteration shades (FAR_PLANE: the covered ones), as
// the composite with OVER_CLEAR would have drawn it over the cleared output from the state the separate
// iteration writes (common/advection_step.glsl: the same arithmetic). COUNT counts the changed pixels.
#include "common/texel.glsl"
#include "common/window_depth.glsl"
#ifdef ADVECT
#include "common/advection_step.glsl"
#endif

#ifdef FAR_PLANE
layout(early_fragment_tests) in;
#endif

// The inputs are read texel by texel as images: on llvmpipe an image load is inlined, where a texelFetch or
// a sample of a float texture calls a generated function.
// p1, p2 (p3): the advected fields (negative where blocked), on the units where an iteration reads the
// state at its pixel (with ADVECT, common/advection_step.glsl declares them); surface: beta, L, linear
// depth, coverage; eigen: |e1| (world), FA; lambda: lambda2'/lambda1', |e1.n|, background grey, cover;
// fibres: packUnorm4x8(|d_k|, weight_k), k = 1..3, and in .w packUnorm4x8(FA, cover, background grey, 0):
// all a fibre set's colour needs of eigen and lambda, in the texel it reads anyway.
#ifndef ADVECT
layout(binding = IMAGE_HERE1, r32f) uniform readonly image2D u_here1;
layout(binding = IMAGE_HERE2, r32f) uniform readonly image2D u_here2;
#ifdef FIBRES
layout(binding = IMAGE_HERE3, r32f) uniform readonly image2D u_here3;
#endif
#endif
#if defined(ADVECT) && !defined(DEPTH_COLOUR)
// The surface's L alone (the projection's light target, unorm16): the one value of the surface a covered
// pixel's colour needs when the depth is not (beta, for blocked pixels, comes with the iteration's vectors).
layout(binding = IMAGE_LIGHT, r16) uniform readonly image2D u_light;
#else
layout(binding = IMAGE_SURFACE, rgba32f) uniform readonly image2D u_surface;
#endif
#ifndef FIBRES
layout(binding = IMAGE_EIGEN, rgba8) uniform readonly image2D u_eigen;
layout(binding = IMAGE_LAMBDA, rgba8) uniform readonly image2D u_lambda;
#endif
#ifdef FIBRES
layout(binding = IMAGE_FIBRES, rgba32ui) uniform readonly uimage2D u_fibres;
#endif

#ifdef WINDOW_DEPTH
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth;           // window depth of the surface
#endif

// The pass's parameters: the uniforms of fabric/composite.vert (described there), received as its flat
// outputs under the uniforms' names.
flat in ivec4 v_place;
flat in ivec2 v_target;
flat in vec2 v_scale;
flat in vec4 v_colourA;
flat in vec4 v_colourB;
flat in vec4 v_colourC;
flat in vec2 v_depthRange;
flat in vec4 v_eyeDepth;
flat in vec3 v_clearColour;
#define u_guard (v_place.xy)
#define u_origin (v_place.zw)
#define u_target v_target
#define u_scale v_scale
#define u_r (v_colourA.x)
#define u_contrast (v_colourA.y)
#define u_lightWeight (v_colourA.z)
#define u_lightMix (v_colourA.w)
#define u_lighting (v_colourB.x > 0.5)
#define u_secondaryRatio (v_colourB.y)
#define u_secondaryFa (v_colourB.z)
#define u_fadeOutOfPlane (v_colourB.w)
#define u_opacityFa (v_colourC.xy)
#define u_depthColour (v_colourC.z)
#define u_sharpen (v_colourC.w)
#define u_depthRange v_depthRange
#define u_eyeDepth v_eyeDepth
#define u_clearColour v_clearColour
#ifdef ANATOMY
const bool kAnatomy = true;
#else
const bool kAnatomy = false;
#endif

#ifdef ADVECT
layout(location = 0) out vec4 o_colour;
layout(location = 1) out float o_p1;
layout(location = 2) out float o_p2;
#ifdef THIRD
layout(location = 3) out float o_p3;
#endif
#else
out vec4 o_colour;
#endif

float stretch(float p) { return clamp(0.5 + u_contrast * (p - 0.5), 0.0, 1.0); }

// The fabric's opacity where there is data: 1 (plain), or the anatomy look's ramp on FA.
float opacity(float fa) {
  return kAnatomy ? smoothstep(u_opacityFa.x, max(u_opacityFa.y, u_opacityFa.x + 1e-3), fa) : 1.0;
}

// What lies beneath the fabric (rgb) and the pixel's alpha: the background volume's grey (alpha 1: it covers
// the whole surface), else in the anatomy look FA as grey, else the fabric itself; without a background
// volume the alpha is the data's cover, so outside the data's edge the framebuffer shows.
vec4 beneath(vec4 lam, float fa, vec3 fabric, float cover, float noiseP) {
#ifdef BACKGROUND
  return vec4(vec3(lam.z), 1.0);
#elif defined(WINDOW_DEPTH)
  // A host's surface is drawn whole: outside the data, the grey noise of "no tensor here".
  return cover > 0.0 ? vec4(kAnatomy ? vec3(fa) : fabric, 1.0) : vec4(vec3(0.45) * (0.6 + 0.4 * noiseP), 1.0);
#else
  return vec4(kAnatomy ? vec3(fa) : fabric, cover);
#endif
}

#ifdef FIBRES
// One population's layer: its DEC colour (FA modulated), brightened by its fabric f, dimmed by its weight.
vec3 layerColour(vec4 pop, float f, float sat, float bright) {
  return mix(vec3(0.35), pop.rgb, sat) * bright * (0.25 + 1.1 * f) * mix(0.35, 1.0, pop.w);
}
// How much a stronger population covers the ones beneath: where its threads are bright, if it has weight.
float cover(vec4 pop, float f) { return smoothstep(0.45, 0.6, f) * smoothstep(0.0, 0.3, pop.w); }
#endif

// The colour and alpha of pixel t from its surface texel s and its advected fields (p1, p2, p3; p3 only
// with FIBRES), as stored: negative where blocked.
vec4 compose(ivec2 t, vec4 s, vec3 fields) {
  if (s.a < 0.5) return vec4(0.0);
  vec2 p = fields.xy;
#ifdef SILHOUETTES
  // The advection blocks exactly the silhouettes, the uncovered pixels and the target's outermost ring, so a
  // covered pixel off the ring is a silhouette where its state is blocked: no fetch of the edge target.
  ivec2 last = u_target - 1;
  float e = p.x < 0.0 && all(greaterThan(t, ivec2(0))) && all(lessThan(t, last)) ? 1.0 : 0.0;
#else
  float e = 0.0;
#endif
  p = mix(p, vec2(s.r), lessThan(p, vec2(0.0))); // blocked (silhouette, target edge): the noise itself
  float L = u_lighting ? s.g : 1.0;
  vec3 c;
  float alpha = 1.0;
#ifdef FIBRES
  uvec4 q = imageLoad(u_fibres, t);
  vec4 attrs = unpackUnorm4x8(q.w); // FA, the data's cover, the background grey
  vec4 lam = vec4(0.0, 0.0, attrs.z, attrs.y); // as lambda holds them (beneath)
  float fa = attrs.x;
  float p3 = fields.z < 0.0 ? s.r : fields.z;
  float f0 = stretch(p.r), f1 = stretch(p.g), f2 = stretch(p3);
  float dataCover = lam.w;
  if (dataCover <= 0.0) {
    c = vec3(0.0);
  } else {
    vec4 pop0 = unpackUnorm4x8(q.x), pop1 = unpackUnorm4x8(q.y), pop2 = unpackUnorm4x8(q.z);
    // Populations by weight, strongest first (the slots follow bundles, not strength); explicit selects
    // instead of dynamically indexed local arrays.
    int o0 = 0, o1 = 1, o2 = 2, tmp;
    float w0 = pop0.w, w1 = pop1.w, w2 = pop2.w;
    if (w1 > w0) { tmp = o0; o0 = o1; o1 = tmp; }
    if (w2 > max(w0, w1)) { tmp = o1; o1 = o0; o0 = 2; o2 = tmp; }
    else if (w2 > min(w0, w1)) { o2 = o1; o1 = 2; }
    vec4 a = o0 == 0 ? pop0 : (o0 == 1 ? pop1 : pop2);
    vec4 b = o1 == 0 ? pop0 : (o1 == 1 ? pop1 : pop2);
    vec4 d = o2 == 0 ? pop0 : (o2 == 1 ? pop1 : pop2);
    float fa0 = o0 == 0 ? f0 : (o0 == 1 ? f1 : f2);
    float fb = o1 == 0 ? f0 : (o1 == 1 ? f1 : f2);
    float fd = o2 == 0 ? f0 : (o2 == 1 ? f1 : f2);
    int last = d.w > 0.02 ? 2 : (b.w > 0.02 ? 1 : 0); // the weakest population shown: the base layer
    float sat = smoothstep(0.05, 0.45, fa), bright = 0.55 + 0.45 * smoothstep(0.05, 0.6, fa);
    c = vec3(0.1) * (0.5 + fa0);
    if (last >= 2) c = layerColour(d, fd, sat, bright);
    if (last >= 1) c = mix(c, layerColour(b, fb, sat, bright), last == 1 ? 1.0 : cover(b, fb));
    c = mix(c, layerColour(a, fa0, sat, bright), last == 0 ? 1.0 : cover(a, fa0));
  }
  vec4 under = beneath(lam, fa, c, dataCover, f0);
  c = mix(under.rgb, c, dataCover * opacity(fa));
  c *= mix(1.0, L, u_lightMix);
  c = mix(c, vec3(0.0), e);
  alpha = under.a;
#elif defined(MEDICAL)
  vec4 eig = imageLoad(u_eigen, t);
  vec4 lam = imageLoad(u_lambda, t);
  float fa = eig.w;
  float p1 = stretch(p.r), p2 = stretch(p.g);
  float cover = lam.w;
  if (cover <= 0.0) {
    c = vec3(0.0);
  } else {
    vec3 dec = abs(eig.xyz);
    // DEC modulated by FA: saturation and brightness grow with FA, so grey matter stays calm.
    vec3 base = mix(vec3(0.35), dec, smoothstep(0.05, 0.45, fa)) * (0.55 + 0.45 * smoothstep(0.05, 0.6, fa));
    vec3 primary = base * (0.25 + 1.1 * p1);
    // Secondary direction: where the in-plane eigenvalues are close or FA is low.
    float ratio = lam.x; // lambda2' / lambda1'
    float w2 = max(smoothstep(u_secondaryRatio, 1.0, ratio), 1.0 - smoothstep(0.0, u_secondaryFa, fa));
    vec3 secondary = vec3(0.2 + 0.6 * p2) * (0.45 + 0.55 * clamp(fa * 2.0, 0.0, 1.0));
    float onTop = smoothstep(0.45, 0.6, p1); // primary threads cover the secondary
    c = mix(primary, mix(secondary, primary, onTop), w2);
#ifdef FADE
    c = mix(c, c * 0.35, u_fadeOutOfPlane * smoothstep(0.6, 0.95, lam.y));
#endif
#ifdef DEC_FA
    c = abs(eig.xyz) * fa;
#endif
  }
  vec4 under = beneath(lam, fa, c, cover, p1);
  c = mix(under.rgb, c, cover * opacity(fa));
  c *= mix(1.0, L, u_lightMix);
  c = mix(c, vec3(0.0), e);
  alpha = under.a;
#else
  float f1 = max(stretch(p.r), 1e-3), f2 = max(stretch(p.g), 1e-3);
  float light = u_lighting ? u_lightWeight * L : 0.0;
  c.r = u_r * f2 / (8.0 * f1 * f1) + e + light;
  c.g = (1.0 - u_r) * f1 / (8.0 * f2 * f2) + e + light;
  c.b = e + light;
  {
    vec4 lam = imageLoad(u_lambda, t);
    float fa = imageLoad(u_eigen, t).w;
    vec4 under = beneath(lam, fa, c, lam.w, stretch(p.r));
    c = mix(under.rgb + e, c, lam.w * opacity(fa));
    alpha = under.a;
  }
#endif
#ifdef DEPTH_COLOUR
  float d = clamp((s.b - u_depthRange.x) / max(u_depthRange.y - u_depthRange.x, 1e-6), 0.0, 1.0);
  c = mix(c, mix(c, vec3(0.35, 0.4, 0.5) * dot(c, vec3(0.333)), 0.8), u_depthColour * d);
#endif
  return vec4(c, alpha);
}

#ifdef ADVECT
void main() {
  ivec2 t = ivec2(gl_FragCoord.xy); // a pixel of the guarded state targets
  vec3 next, here;
  float beta;
  bool moving = advectionStep(t, next, here, beta);
  vec3 fields = moving ? next : here;
  o_p1 = fields.x;
  o_p2 = fields.y;
#ifdef THIRD
  o_p3 = fields.z;
#else
  fields.z = BLOCKED; // a two-field fabric of a fibre set: no third thread field
#endif
#ifdef DEPTH_COLOUR
  vec4 s = imageLoad(u_surface, t);
#else
  // Every pixel shaded here is covered (surface.a = 1: the early depth test passes where the tensor stage's
  // did); the linear depth is read only for DEPTH_COLOUR.
  vec4 s = vec4(beta, imageLoad(u_light, t).r, 0.0, 1.0);
#endif
  vec4 composed = compose(t, s, fields);
  // Where the composite would discard, the cleared output's colour stays.
  o_colour = vec4(composed.a > 0.0 ? mix(u_clearColour, clamp(composed.rgb, 0.0, 1.0), composed.a) : u_clearColour,
                  1.0);
}
#else
// The fields at pixel t as the state holds them.
vec3 fieldsAt(ivec2 t) {
#ifdef FIBRES
  return vec3(imageLoad(u_here1, t).r, imageLoad(u_here2, t).r, imageLoad(u_here3, t).r);
#else
  return vec3(imageLoad(u_here1, t).r, imageLoad(u_here2, t).r, 0.0);
#endif
}

void main() {
  ivec2 t = ivec2((gl_FragCoord.xy - vec2(u_origin)) * u_scale) + u_guard;
  vec4 s = imageLoad(u_surface, t);
  if (s.a < 0.5) discard;
  vec4 composed = compose(t, s, fieldsAt(t));
  if (composed.a <= 0.0) discard; // outside the data's edge, no background volume
  vec3 c = composed.rgb;
#ifdef SHARPEN
  {
    vec3 sum = vec3(0.0);
    float n = 0.0;
    for (int i = 0; i < 4; ++i) {
      ivec2 q = t + ivec2(i == 0 ? 1 : (i == 1 ? -1 : 0), i == 2 ? 1 : (i == 3 ? -1 : 0));
      if (imageLoad(u_surface, q).a > 0.5) {
        sum += compose(q, imageLoad(u_surface, q), fieldsAt(q)).rgb;
        n += 1.0;
      }
    }
    if (n > 0.0) c += u_sharpen * (c - sum / n);
  }
#endif
#ifdef OVER_CLEAR
  o_colour = vec4(mix(u_clearColour, clamp(c, 0.0, 1.0), composed.a), 1.0); // straight alpha over the clear
#else
  o_colour = vec4(clamp(c, 0.0, 1.0), composed.a);
#endif
#ifdef WINDOW_DEPTH
  // Two units of a 24-bit depth buffer nearer (1.2e-7): the conversion of the written float back to the
  // host's fixed-point buffer may round up by one unit, which would fail GL_LEQUAL on the host's own surface.
  gl_FragDepth = max(texel(u_depth, t).r - 2.0 / 16777215.0, 0.0);
#elif !defined(FAR_PLANE)
  gl_FragDepth = windowDepth(u_eyeDepth, s.b);
#endif
}
#endif
