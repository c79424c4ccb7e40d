// SPDX-License-Identifier: GPL-3.0-or-later
// The tensor stage's parameters (common/projection_pixel.glsl and the field samplers it includes). The
// compute pass (COMPUTE) reads them as uniforms. The fragment pass receives them as flat inputs from
// fabric/projection.vert, which reads the uniforms (FORWARD_PARAMS) three times a draw: on llvmpipe a
// fragment shader pays for each read of a uniform component on every block of pixels, about four times
// what a flat input costs. Either way the code below them uses the uniforms' names. The largest variant
// (FIBRES BACKGROUND UNCERTAINTY ALONG) hands on 114 components, 120 with the ray's: within the 128 that desktop
// GL 4.5 drivers offer (the specification's minimum for a vertex shader's outputs is 64).
#if defined(COMPUTE) || defined(FORWARD_PARAMS)
uniform mat4 u_eyeToWorld;
uniform mat4 u_viewProj;
uniform mat3 u_viewRot;      // world -> eye rotation (normals)
uniform mat4 u_worldToTex;   // world RAS mm -> the field's texture coordinates
uniform vec2 u_targetSize;   // guarded target size in pixels
uniform float u_eps;         // mm; finite-difference step along the eigenvectors
uniform float u_degenerateTol = 0.02; // relative in-plane eigenvalue gap below which there is no direction
uniform bool u_orthographic;
uniform float u_pixelMm;         // orthographic: pixel size in mm
uniform float u_pixelMmPerDepth; // perspective: pixel size in mm per mm of depth
uniform float u_lod;         // l of Eq. 7: implicit voxel edge in mm
uniform vec3 u_noiseOrigin;  // b_min of Eq. 7 (world mm)
uniform float u_noiseBlend = 0.5; // NOISE_BLEND: > 0 softens the switch between voxel faces
uniform float u_faFloor = 0.0; // the fabric only where FA >= u_faFloor
uniform float u_ambient = 0.25; // Blinn-Phong material (common/lighting.glsl)
uniform float u_diffuse = 0.65;
uniform float u_specular = 0.35;
#ifdef FIBRES
uniform int u_lobeCount = 1; // 1..3 slots uploaded
#endif
#ifdef BACKGROUND
uniform mat4 u_backgroundWorldToTex;
#endif
#ifdef UNCERTAINTY
uniform mat4 u_uncertaintyWorldToTex;
uniform float u_fray = 1.0;       // strength: the turn is up to u_fray x the cone
uniform float u_frayCells = 16.0; // noise cells per implicit voxel edge
#endif
#ifdef ALONG
uniform vec3 u_alongScale;  // world RAS mm -> the proximity weight's texture coordinates (an axis-aligned
uniform vec3 u_alongOffset; // grid): world * scale + offset
#endif
#endif

#ifndef COMPUTE
#ifdef FORWARD_PARAMS
#define PARAMS_VARYING flat out
#else
#define PARAMS_VARYING flat in
#endif
PARAMS_VARYING mat4 v_eyeToWorld;
PARAMS_VARYING mat4 v_viewProj;
PARAMS_VARYING mat3 v_viewRot;
PARAMS_VARYING mat4 v_worldToTex;
PARAMS_VARYING vec4 v_view;     // target size, eps, degenerate tolerance
PARAMS_VARYING vec4 v_pixel;    // orthographic (1 or 0), pixel mm, pixel mm per depth, lod
PARAMS_VARYING vec4 v_noise;    // noise origin, noise blend
PARAMS_VARYING vec4 v_material; // FA floor, ambient, diffuse, specular
#ifdef FIBRES
PARAMS_VARYING int v_lobeCount;
#endif
#ifdef BACKGROUND
PARAMS_VARYING mat4 v_backgroundWorldToTex;
#endif
#ifdef UNCERTAINTY
PARAMS_VARYING mat4 v_uncertaintyWorldToTex;
PARAMS_VARYING vec2 v_fray;     // fray, fray cells
#endif
#ifdef ALONG
PARAMS_VARYING vec3 v_alongScale;
PARAMS_VARYING vec3 v_alongOffset;
#endif

#ifdef FORWARD_PARAMS
void forwardParams() {
  v_eyeToWorld = u_eyeToWorld;
  v_viewProj = u_viewProj;
  v_viewRot = u_viewRot;
  v_worldToTex = u_worldToTex;
  v_view = vec4(u_targetSize, u_eps, u_degenerateTol);
  v_pixel = vec4(u_orthographic ? 1.0 : 0.0, u_pixelMm, u_pixelMmPerDepth, u_lod);
  v_noise = vec4(u_noiseOrigin, u_noiseBlend);
  v_material = vec4(u_faFloor, u_ambient, u_diffuse, u_specular);
#ifdef FIBRES
  v_lobeCount = u_lobeCount;
#endif
#ifdef BACKGROUND
  v_backgroundWorldToTex = u_backgroundWorldToTex;
#endif
#ifdef UNCERTAINTY
  v_uncertaintyWorldToTex = u_uncertaintyWorldToTex;
  v_fray = vec2(u_fray, u_frayCells);
#endif
#ifdef ALONG
  v_alongScale = u_alongScale;
  v_alongOffset = u_alongOffset;
#endif
}
#else
#define u_eyeToWorld v_eyeToWorld
#define u_viewProj v_viewProj
#define u_viewRot v_viewRot
#define u_worldToTex v_worldToTex
#define u_targetSize (v_view.xy)
#define u_eps (v_view.z)
#define u_degenerateTol (v_view.w)
#define u_orthographic (v_pixel.x > 0.5)
#define u_pixelMm (v_pixel.y)
#define u_pixelMmPerDepth (v_pixel.z)
#define u_lod (v_pixel.w)
#define u_noiseOrigin (v_noise.xyz)
#define u_noiseBlend (v_noise.w)
#define u_faFloor (v_material.x)
#define u_ambient (v_material.y)
#define u_diffuse (v_material.z)
#define u_specular (v_material.w)
#define u_lobeCount v_lobeCount
#define u_backgroundWorldToTex v_backgroundWorldToTex
#define u_uncertaintyWorldToTex v_uncertaintyWorldToTex
#define u_fray (v_fray.x)
#define u_frayCells (v_fray.y)
#define u_alongScale v_alongScale
#define u_alongOffset v_alongOffset
#endif
#endif
