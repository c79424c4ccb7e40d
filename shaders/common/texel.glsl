// SPDX-License-Identifier: GPL-3.0-or-later
// The texel at integer coordinates p, read as a sample at its centre. The unit must have a nearest sampler
// (the texture's own filter, or createTexelSampler bound over it); then the result is texelFetch's:
// (p + 0.5) / size * size stays well inside texel p. On llvmpipe a texelFetch costs about twice a nearest
// sample (it calls a generated function that also checks the level and the bounds). For textures an image
// unit takes, an imageLoad is cheaper still (inlined), and the fabric's passes use those where they run per
// frame or per view; this serves the host's textures, depth textures (which no image unit takes), and the
// movie frames' restart: the silhouette pass's target and the previous frame's surface.
vec4 texel(sampler2D s, ivec2 p) { return texture(s, (vec2(p) + 0.5) / vec2(textureSize(s, 0))); }
