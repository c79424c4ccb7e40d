#version 450 core
// The Eq. 12 iteration of fabric/advection.frag as a compute shader (the same common/advection_step.glsl),
// for GPUs whose fragment pipeline is the narrow part of the chip (AdvectionPass::setCompute). Blocked
// pixels are not written: the restart gave them the blocked state in both ping-pong textures, as the
// fragment pass's early depth test leaves the background.
layout(local_size_x = 8, local_size_y = 8) in;
#include "common/advection_step.glsl"
layout(binding = IMAGE_NEXT1, r32f) uniform writeonly image2D o_p1;
layout(binding = IMAGE_NEXT2, r32f) uniform writeonly image2D o_p2;
#ifdef THIRD
layout(binding = IMAGE_NEXT3, r32f) uniform writeonly image2D o_p3;
#endif

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, textureSize(u_prev1, 0)))) return;
  vec3 next, here;
  if (!advectionStep(p, next, here)) return;
  imageStore(o_p1, p, vec4(next.x));
  imageStore(o_p2, p, vec4(next.y));
#ifdef THIRD
  imageStore(o_p3, p, vec4(next.z));
#endif
}
