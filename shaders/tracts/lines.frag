#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Tract overlay colour: DEC of the world tangent (|t.x| red, |t.y| green, |t.z| blue), lit with the
// tangent-based line lighting of Zöckler, Stalling and Hege with a headlight along the eye-space view
// axis (L = V = +z, exact for orthographic views): diffuse = sqrt(1 - (L.t)^2), specular =
// (1 - 2 (L.t)^2)^8; darkened towards the tube's edges. Fragments farther than u_slabMm from the slab
// plane are discarded (u_slabMm <= 0: no slab). Points with a node (g_node >= 0, rounded) take
// u_nodeColour[node] when u_nodeColoured and its alpha is 1 (the profile's value), and the highlighted node
// and those within u_highlightHalfWidth nodes of it are drawn in u_highlightColour, unlit.
in vec3 g_tangent;
in float g_across;
in float g_planeDist;
in vec4 g_colour; // alpha 1: a value colour replaces DEC
in float g_node;  // < 0: no node
uniform int u_highlightNode = -1;
uniform int u_highlightHalfWidth = 1;
uniform vec3 u_highlightColour = vec3(1.0, 1.0, 0.25);
uniform bool u_nodeColoured = false;
uniform vec4 u_nodeColour[128];
uniform mat3 u_viewRot;
uniform float u_slabMm;
uniform float u_ambient = 0.35;
uniform float u_diffuse = 0.6;
uniform float u_specular = 0.3;
out vec4 o_colour;

void main() {
  if (u_slabMm > 0.0 && abs(g_planeDist) > u_slabMm) discard;
  vec3 t = normalize(g_tangent);
  vec3 te = u_viewRot * t;
  float lt = te.z; // L = V = +z in eye space (orthographic headlight)
  float sinLt = sqrt(max(1.0 - lt * lt, 0.0));
  float spec = max(sinLt * sinLt - lt * lt, 0.0);
  spec *= spec;
  spec *= spec;
  spec *= spec;
  float tube = sqrt(max(1.0 - g_across * g_across, 0.0));
  float light = (u_ambient + u_diffuse * sinLt) * (0.55 + 0.45 * tube) + u_specular * spec * tube;
  vec3 base = g_colour.a > 0.5 ? g_colour.rgb : abs(t);
  if (g_node >= 0.0) {
    int node = int(floor(g_node + 0.5));
    if (u_highlightNode >= 0 && abs(node - u_highlightNode) <= u_highlightHalfWidth) {
      o_colour = vec4(u_highlightColour, 1.0);
      return;
    }
    if (u_nodeColoured && node < 128 && u_nodeColour[node].a > 0.5) base = u_nodeColour[node].rgb;
  }
  o_colour = vec4(clamp(base * light, 0.0, 1.0), 1.0);
}
