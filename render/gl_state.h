// SPDX-License-Identifier: GPL-3.0-or-later
// The GL state the renderers change or depend on, saved and restored around their public entry points, so
// that a frame leaves the state as it found it (a host application's state survives it) and a host's state
// cannot change what the passes draw: framebuffers, viewports, depth range and clip control, the switches
// (depth/blend/cull/scissor/stencil test, polygon offset, depth clamp, rasterizer discard, logic op, sRGB
// writes, clip distances), depth mask and function, colour masks, cull face and front face, polygon mode,
// program, vertex array, the active texture unit, the 2D and 3D textures and sampler objects bound to the
// first units, the image units GL 4.5 guarantees (the passes read and write images), the atomic counter
// buffer bindings, the pixel pack/unpack buffers and pixel store
// parameters, the blend functions and equations (of draw buffer 0; restored for all), the scissor boxes
// (the composite and the advection's restarts scissor). Clear values and stencil functions are not
// touched by the passes (they clear with glClearNamedFramebuffer* and never enable the stencil test).
#pragma once

#include <array>
#include <epoxy/gl.h>
#include <string>

namespace dtf::render {

struct GlState {
  static constexpr int kTextureUnits = 16;
  static constexpr int kImageUnits = 8; // GL_MAX_IMAGE_UNITS is at least 8; the passes use units 0..7
  static constexpr int kViewports = 16;  // GL 4.5 guarantees at least 16 viewports
  static constexpr int kDrawBuffers = 8; // and at least 8 draw buffers
  static constexpr int kClipDistances = 8;
  // The pixel store parameters, pack then unpack: swap bytes, LSB first, row length, image height, skip
  // rows, skip pixels, skip images, alignment.
  static constexpr int kPixelStore = 16;

  GLint drawFramebuffer = 0, readFramebuffer = 0;
  std::array<GLint, 4> viewport{};                            // viewport 0
  std::array<std::array<GLfloat, 4>, kViewports> viewports{}; // all viewports (glViewport sets every one)
  std::array<std::array<GLint, 4>, kViewports> scissorBoxes{}; // per viewport (glScissor sets every one)
  std::array<GLdouble, 2> depthRange{0.0, 1.0};
  GLint clipOrigin = GL_LOWER_LEFT, clipDepthMode = GL_NEGATIVE_ONE_TO_ONE;
  GLboolean depthTest = GL_FALSE, blend = GL_FALSE, cullFace = GL_FALSE, scissorTest = GL_FALSE;
  GLboolean stencilTest = GL_FALSE, polygonOffsetFill = GL_FALSE, depthClamp = GL_FALSE;
  GLboolean rasterizerDiscard = GL_FALSE, colourLogicOp = GL_FALSE, framebufferSrgb = GL_FALSE;
  std::array<GLboolean, kDrawBuffers> blendi{}; // per draw buffer (glEnablei)
  std::array<GLint, 4> blendFunc{GL_ONE, GL_ZERO, GL_ONE, GL_ZERO}; // src RGB, dst RGB, src alpha, dst alpha
  std::array<GLint, 2> blendEquation{GL_FUNC_ADD, GL_FUNC_ADD};      // RGB, alpha
  std::array<GLboolean, kClipDistances> clipDistance{};
  GLboolean depthMask = GL_TRUE;
  GLint depthFunc = GL_LESS;
  std::array<std::array<GLboolean, 4>, kDrawBuffers> colourMask{};
  GLint cullFaceMode = GL_BACK, frontFace = GL_CCW;
  std::array<GLint, 2> polygonMode{GL_FILL, GL_FILL};
  GLint program = 0, vertexArray = 0, activeTexture = GL_TEXTURE0, atomicCounterBuffer = 0;
  // The current program was deleted while in use (GL_DELETE_STATUS): GL frees it as soon as another
  // program is made current, so restore() cannot bring it back and leaves no program current instead of
  // binding a freed name (GL_INVALID_VALUE, or another program where the driver reuses names).
  GLboolean programDeleted = GL_FALSE;
  GLint atomicCounterBuffer0 = 0; // indexed binding 0 with its range
  GLint64 atomicCounterStart0 = 0, atomicCounterSize0 = 0;
  GLint pixelPackBuffer = 0, pixelUnpackBuffer = 0;
  std::array<GLint, kPixelStore> pixelStore{0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 4};
  std::array<GLint, kTextureUnits> textures2d{};
  std::array<GLint, kTextureUnits> textures3d{};
  std::array<GLint, kTextureUnits> samplers{};
  // Per image unit: texture, level, layered, layer, access, format (the GL's initial values by default).
  std::array<std::array<GLint, 6>, kImageUnits> images = [] {
    std::array<std::array<GLint, 6>, kImageUnits> a{};
    for (auto& i : a) i = {0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8};
    return a;
  }();

  // Reads the current context's state.
  static GlState capture();
  // Makes it current again.
  void restore() const;
  bool operator==(const GlState&) const = default;
  // The names of the fields that differ from `other` with both values, e.g. "depthFunc 513 != 516"
  // (empty when equal).
  std::string differences(const GlState& other) const;
};

// Saves the state on construction and restores it on destruction. The passes inside start from GL's
// defaults: depth test, blend, cull face, scissor and stencil test, polygon offset, depth clamp, rasterizer
// discard, logic op, sRGB writes and clip distances off; depth mask and colour masks on, GL_LESS, back faces
// culled, counter-clockwise front faces, filled polygons, depth range [0, 1], lower-left origin and [-1, 1]
// depth clip control, no sampler objects on the first units, no pixel pack/unpack buffer and the default
// pixel store parameters.
class GlStateGuard {
public:
  GlStateGuard();
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;
  // The state found on construction.
  const GlState& saved() const { return saved_; }

private:
  GlState saved_;
};

} // namespace dtf::render
