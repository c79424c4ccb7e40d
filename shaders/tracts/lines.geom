#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Widens each line segment into a screen-aligned quad (tube impostor) u_widthPx pixels wide, extended by
// half the width at both ends so consecutive segments overlap at the joints. Passes the segment's world
// tangent for DEC colour and line lighting, and the across-line coordinate for the tube shading.
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
in vec3 v_world[];
in float v_planeDist[];
in vec4 v_colour[];
in float v_node[];
uniform mat4 u_view;
uniform mat4 u_proj;
uniform vec2 u_viewport;      // pixels
uniform float u_widthPx;
uniform float u_depthBiasMm;  // moves the line towards the viewer (lines lying in a surface stay visible)
out vec3 g_tangent;           // world, unit
out float g_across;           // -1 .. 1 across the tube
out float g_planeDist;
out vec4 g_colour;
out float g_node;               // interpolated along the segment: each half takes its end's node

void main() {
  vec3 d = v_world[1] - v_world[0];
  float len = length(d);
  if (len <= 0.0) return;
  vec3 t = d / len;
  vec4 e0 = u_view * vec4(v_world[0], 1.0), e1 = u_view * vec4(v_world[1], 1.0);
  e0.z += u_depthBiasMm;
  e1.z += u_depthBiasMm;
  vec4 c0 = u_proj * e0, c1 = u_proj * e1;
  if (c0.w <= 0.0 || c1.w <= 0.0) return; // behind the eye (perspective)
  vec2 s0 = c0.xy / c0.w * 0.5 * u_viewport, s1 = c1.xy / c1.w * 0.5 * u_viewport;
  vec2 dir = s1 - s0;
  float sl = length(dir);
  dir = sl > 1e-4 ? dir / sl : vec2(1.0, 0.0);
  vec2 nrm = vec2(-dir.y, dir.x);
  float h = 0.5 * u_widthPx;
  vec2 off = nrm * h, ext = dir * h;
  vec2 toNdc = 2.0 / u_viewport;
  vec2 corner[4] = vec2[](-ext - off, -ext + off, ext - off, ext + off);
  float across[4] = float[](-1.0, 1.0, -1.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    vec4 c = i < 2 ? c0 : c1;
    gl_Position = vec4(c.xy + corner[i] * toNdc * c.w, c.z, c.w);
    g_tangent = t;
    g_across = across[i];
    g_planeDist = v_planeDist[i < 2 ? 0 : 1];
    g_colour = v_colour[i < 2 ? 0 : 1];
    g_node = v_node[i < 2 ? 0 : 1];
    EmitVertex();
  }
  EndPrimitive();
}
