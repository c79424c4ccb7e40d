#version 450 core
// Projection pass, geometry stage: one RGBA32F texel per covered pixel, (world normal as interpolated,
// linear eye depth in mm). The target is cleared to 0, so depth 0 means "no surface here". The shader
// is trivial on purpose: on a software rasteriser each small triangle costs a full block of fragment
// invocations, so the expensive per-pixel work runs once per pixel in the fullscreen stage instead.
in vec3 v_normal;
in float v_depth;

layout(location = 0) out vec4 o_geometry;

void main() { o_geometry = vec4(v_normal, max(v_depth, 1e-6)); }
