#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The tract layer over the fabric (render/tract_layer.h): the layer's colour where a tract was drawn (alpha
// 1), else the fabric's. Same size as the output; depth is left as the fabric wrote it.
layout(binding = UNIT_FABRIC) uniform sampler2D u_fabric;
layout(binding = UNIT_LAYER) uniform sampler2D u_layer;
out vec4 o_colour;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 t = texelFetch(u_layer, p, 0);
  o_colour = t.a > 0.0 ? vec4(t.rgb, 1.0) : texelFetch(u_fabric, p, 0);
}
