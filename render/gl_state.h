// The GL state the renderers change, saved and restored around their public entry points, so that a frame
// leaves the state as it found it (a host application's state survives it): framebuffers, viewport,
// depth/blend/cull/scissor switches, depth mask and function, program, vertex array, the active texture
// unit, the textures bound to the first units, the atomic counter buffer binding and the pack/unpack row
// alignment.
#pragma once

#include <array>
#include <epoxy/gl.h>

namespace dtf::render {

struct GlState {
  static constexpr int kTextureUnits = 16;
  GLint drawFramebuffer = 0, readFramebuffer = 0;
  std::array<GLint, 4> viewport{};
  GLboolean depthTest = GL_FALSE, blend = GL_FALSE, cullFace = GL_FALSE, scissorTest = GL_FALSE;
  GLboolean depthMask = GL_TRUE;
  GLint depthFunc = GL_LESS;
  GLint program = 0, vertexArray = 0, activeTexture = GL_TEXTURE0, atomicCounterBuffer = 0;
  GLint packAlignment = 4, unpackAlignment = 4;
  std::array<GLint, kTextureUnits> textures2d{};

  // Reads the current context's state.
  static GlState capture();
  // Makes it current again.
  void restore() const;
  bool operator==(const GlState&) const = default;
};

// Saves the state on construction and restores it on destruction. The passes inside start from GL's
// defaults for the switches (depth test, blend, cull face, scissor test off; depth mask on, GL_LESS).
class GlStateGuard {
public:
  GlStateGuard();
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

private:
  GlState saved_;
};

} // namespace dtf::render
