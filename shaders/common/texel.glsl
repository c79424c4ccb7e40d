// The texel at integer coordinates p, read as a sample at its centre. The unit must have a nearest sampler
// (the texture's own filter, or createTexelSampler bound over it); then the result is texelFetch's:
// (p + 0.5) / size * size stays well inside texel p. On llvmpipe a texelFetch costs about twice a nearest
// sample (it calls a generated function that also checks the level and the bounds). For textures an image
// unit takes, an imageLoad is cheaper still (inlined): the advection's iterations and the composite use
// those; this serves the restarts, the projection, the host import and depth textures.
vec4 texel(sampler2D s, ivec2 p) { return texture(s, (vec2(p) + 0.5) / vec2(textureSize(s, 0))); }
uvec4 texel(usampler2D s, ivec2 p) { return texture(s, (vec2(p) + 0.5) / vec2(textureSize(s, 0))); }
