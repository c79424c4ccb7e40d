// SPDX-License-Identifier: GPL-3.0-or-later
// The embedding API: the fabric drawn into a host application's own GL scene. The host keeps its context,
// camera and geometry; it renders the surfaces to texture into a depth texture and a world-normal texture
// (its own geometry pass) and hands them over with its view and projection matrices, the viewport and the
// framebuffer to draw into. EmbeddedFabric then runs the fabric's passes (tensor stage, silhouette,
// advection, composite; the same passes as dtfabric's own front ends, which differ only in filling the
// geometry buffers from a mesh) and composites into the host's framebuffer and viewport, depth-tested
// against the host's depth, and leaves every piece of GL state as it found it.
// No GL header here: GL object names are plain unsigned ints. Needs a current OpenGL 4.5 core context
// (the host's) for every call, the same one each time.
//
//   dtf::render::EmbeddedFabric fabric;             // once, with the host's context current
//   fabric.setField(dtf::io::readTensorVolume(path).field);
//   // every frame, after the host's geometry pass:
//   dtf::render::HostView v;
//   v.depthTexture = depthTex; v.normalTexture = normalTex;
//   v.view = view; v.projection = projection; v.viewport = {x, y, w, h}; v.framebuffer = fbo;
//   fabric.draw(v, dtf::render::FabricParams{});
#pragma once

#include "io/model/fibre_set.h"
#include "io/model/tensor_field.h"
#include "render/fabric_params.h"

#include <glm/glm.hpp>
#include <memory>

namespace dtf::render {

// How the host's normal texture stores a world normal n.
enum class NormalEncoding {
  Signed, // the texel is n: float or signed normalised formats (GL_RGB16F, GL_RGBA32F, GL_RGBA16_SNORM, ...)
  Biased, // the texel is 0.5 n + 0.5: unsigned normalised formats (GL_RGBA8, GL_RGB10_A2, GL_RGBA16, ...)
};

// What the host hands over each frame. Both textures are GL_TEXTURE_2D names addressed in the pixels of the
// framebuffer they were rendered for, at least viewport.x + width by viewport.y + height, level 0 sampled,
// with nearest sampling and no depth comparison whatever the textures' own parameters.
struct HostView {
  // Window depth of the surfaces to texture: any depth format (GL_DEPTH_COMPONENT16/24/32F, or
  // GL_DEPTH24_STENCIL8 / GL_DEPTH32F_STENCIL8 in their default depth sampling mode), rendered with the
  // default glDepthRange(0, 1) and glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE); 1 (the far plane,
  // the usual clear value) means no surface.
  unsigned depthTexture = 0;
  // World-space normals of the same surfaces (RAS mm frame; any length, need not face the camera). A zero
  // normal also means no surface, so a host can mask pixels out by clearing the normal texture to 0.
  unsigned normalTexture = 0;
  NormalEncoding normalEncoding = NormalEncoding::Signed;
  glm::mat4 view{1.0f};       // world RAS mm -> eye: rotation and translation, as used for the textures
  glm::mat4 projection{1.0f}; // eye -> clip (GL conventions; perspective or orthographic)
  glm::ivec4 viewport{0};     // x, y, width, height in pixels, lower-left origin: where the surfaces are in
                              // the textures and where the fabric goes in the framebuffer
  // The framebuffer drawn into (0: the default framebuffer). The fabric writes fragment output 0 only: set
  // the framebuffer's other draw buffers to GL_NONE (GL leaves outputs a shader does not write undefined).
  unsigned framebuffer = 0;
};

class EmbeddedFabric {
public:
  // Compiles the programs in the current context. Throws dtf::GlError (no GL 4.5 context, compile failure).
  EmbeddedFabric();
  ~EmbeddedFabric();
  EmbeddedFabric(const EmbeddedFabric&) = delete;
  EmbeddedFabric& operator=(const EmbeddedFabric&) = delete;
  EmbeddedFabric(EmbeddedFabric&&) noexcept;
  EmbeddedFabric& operator=(EmbeddedFabric&&) noexcept;

  // The tensor field (world RAS mm, mm^2/s), uploaded once. Its voxel centres' bounding box anchors the noise
  // (b_min of Eq. 7), so every surface cut from this field textures consistently. Throws dtf::GlError when
  // it does not fit the GPU.
  void setField(const TensorField& field);
  // A fibre set for ColourMode::Fibres, with the FA of a paired tensor (nullptr: none).
  void setFibres(const FibreSet& fibres, const ScalarVolume* fa = nullptr);
  void clearFibres();
  // A grey volume shown where a surface has no tensor data, windowed to [lo, hi]; nullptr removes it.
  void setBackground(const ScalarVolume* volume, float lo = 0.0f, float hi = 1.0f);

  // One interactive frame into view.framebuffer at view.viewport: params.iterations advection steps that
  // continue the previous frame's state; the state restarts from the noise when the matrices, viewport,
  // textures, data or parameters change (or after restart()). Fabric pixels replace the host's colour where
  // the depth texture has a surface and the framebuffer's depth (if it has one) passes GL_LEQUAL against
  // that surface's depth, and write that depth (less two units of a 24-bit buffer, so that round-off in the
  // conversion never fails the test on the host's own surface); other pixels keep the host's colour and
  // depth. In the guard border around the viewport (FabricParams::guard), where the host has no data, the
  // surface is continued along the tangent plane of the viewport's edge pixels. Draws nothing without data.
  // No allocation per frame; the internal targets are re-created only when the viewport's size changes.
  // FabricParams::movingScale does not apply (the host decides its resolution). Throws dtf::GlError for an
  // unusable view (no texture, too small, not 2D, viewport out of range).
  void draw(const HostView& view, const FabricParams& params);
  // A converged still of the same (see FabricRenderer::renderStill): deterministic.
  void drawStill(const HostView& view, const FabricParams& params);
  // The next draw() restarts the advection (e.g. the host's geometry changed under the same matrices).
  void restart();

  // GL_TIME_ELAPSED queries around the passes; lastTimes() waits for the last frame's results. The
  // projection time covers the import of the host's textures and the tensor stage.
  void setTiming(bool on);
  PassTimes lastTimes() const;
  // Advection iterations of the last drawStill.
  int lastIterations() const;
  // The tensor stage and the advection as compute shaders or as fullscreen draws
  // (FabricRenderer::setComputePasses).
  void setComputePasses(bool on);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace dtf::render
