#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Tensor stage of the projection (paper §2.1 and §2.3, Eq. 1-5 and 7-9): once per covered pixel of the
// geometry buffers, written from a mesh (fabric/geometry.*) or imported from a host's depth and normal
// textures (fabric/host_import.frag); the early depth test against their depth skips the rest (see
// common/deferred.vert).
// Per pixel: rebuild the world position from the linear depth, interpolate the tensor, project it onto the
// tangent plane (T' = P T P^T, P = I - n n^T), decompose T', take its two in-plane eigenvectors, project
// each to image space as the pixel difference of p + eps v and p (perspective-correct), and scale by the
// max-norm. Also writes the mapped noise beta, light intensity, depth, FA, the ratio of the in-plane
// eigenvalues and the 3D principal eigenvector's DEC colour. A zero vector means "no direction here".
// Variants (compile-time, since a software rasteriser pays for untaken branches): WITH_PRINCIPAL (3D
// eigenvector for the medical colours), NOISE_BLEND (softened face switch), BACKGROUND (grey volume where
// there is no tensor data), FIBRES (a fibre set instead of the tensor: up to three matched lobes, see
// common/fibre_field.glsl, each projected onto the surface (P d) and to image space like the eigenvectors;
// the vectors hold populations 1 and 2, o_fibres per population its DEC colour |d| and weight
// amplitude / strongest x in-surface fraction |P d|, o_vectors3 the vectors and population 3's direction).
#include "common/projection_pixel.glsl"

layout(early_fragment_tests) in;

noperspective in vec3 v_nearEye;
noperspective in vec3 v_farEye;

// Image-space directions v1.xy, v2.xy (max-norm 1) and beta, packed in 8 bytes (packVectors in
// common/projection_pixel.glsl): everything an advection iteration reads of the projection in one fetch.
layout(location = 0) out uvec2 o_vectors;
layout(location = 1) out vec4 o_surface; // beta, light L, linear depth (mm from the eye), 1 = covered
layout(location = 2) out vec4 o_eigen;   // |e1| (world principal eigenvector of T, DEC colour), FA
layout(location = 3) out vec4 o_lambda;  // lambda2'/lambda1', |e1 . n|, background grey, data cover (0..1)
layout(location = 4) out float o_light;  // L again (R16: the composite's 2-byte read per frame)
#ifdef FIBRES
layout(location = 5) out uvec4 o_fibres; // packUnorm4x8(|d_k|, weight_k), k = 1..3; .w fibreAttributes
// The vectors texel (.xy) and population 3's image direction (.z, snorm16 v3.xy): a three-field iteration's
// one fetch of the projection.
layout(location = 6) out uvec4 o_vectors3;
#endif

void main() {
  float edge;
  Projection p = projectPixel(ivec2(gl_FragCoord.xy), v_nearEye, v_farEye, edge);
  p.lambda.w *= coverRamp(edge, fwidth(edge));
  o_vectors = p.vectors;
  o_surface = p.surface;
  o_eigen = p.eigen;
  o_lambda = p.lambda;
  o_light = p.surface.g;
#ifdef FIBRES
  o_fibres = uvec4(p.fibres.xyz, fibreAttributes(p));
  o_vectors3 = p.vectors3;
#endif
}
