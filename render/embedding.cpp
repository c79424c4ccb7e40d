// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/embedding.h"

#include "io/model/error.h"
#include "render/fabric/fabric_pipeline.h"
#include "render/gl_state.h"

#include <algorithm>
#include <string>

namespace dtf::render {

namespace {

// Checks that `id` names a 2D texture that covers `extent`; throws GlError naming `what` otherwise.
void checkTexture(unsigned id, const char* what, glm::ivec2 extent) {
  if (id == 0 || !glIsTexture(id))
    throw GlError(std::string("EmbeddedFabric: ") + what + " is not a texture");
  GLint target = 0, w = 0, h = 0;
  glGetTextureParameteriv(id, GL_TEXTURE_TARGET, &target);
  if (target != GL_TEXTURE_2D)
    throw GlError(std::string("EmbeddedFabric: ") + what + " is not a GL_TEXTURE_2D");
  glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_WIDTH, &w);
  glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_HEIGHT, &h);
  if (w < extent.x || h < extent.y)
    throw GlError(std::string("EmbeddedFabric: ") + what + " is " + std::to_string(w) + "x" +
                  std::to_string(h) + ", the viewport needs " + std::to_string(extent.x) + "x" +
                  std::to_string(extent.y));
}

} // namespace

struct EmbeddedFabric::Impl {
  FabricPipeline pipeline;
  FrameView view;
  // What the last frame imported: a change restarts the advection.
  unsigned depthTexture = 0, normalTexture = 0;
  glm::ivec4 viewport{0};
  int lastIterations = 0;

  // Imports the host's textures and runs the tensor stage and silhouettes; false when there is nothing to
  // draw (no data).
  bool prepare(const HostView& v, const FabricParams& p, bool still);
};

bool EmbeddedFabric::Impl::prepare(const HostView& v, const FabricParams& p, bool still) {
  const glm::ivec2 size(v.viewport.z, v.viewport.w);
  if (size.x < 1 || size.y < 1 || size.x > 16384 || size.y > 16384 || v.viewport.x < 0 || v.viewport.y < 0)
    throw GlError("EmbeddedFabric: viewport " + std::to_string(v.viewport.x) + " " +
                  std::to_string(v.viewport.y) + " " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                  " out of range");
  const glm::ivec2 extent(v.viewport.x + size.x, v.viewport.y + size.y);
  checkTexture(v.depthTexture, "the depth texture", extent);
  checkTexture(v.normalTexture, "the normal texture", extent);
  if (v.framebuffer != 0 && !glIsFramebuffer(v.framebuffer))
    throw GlError("EmbeddedFabric: " + std::to_string(v.framebuffer) + " is not a framebuffer");
  pipeline.clearTimers();
  glm::vec3 lo, hi;
  if (!pipeline.dataBounds(lo, hi)) return false;
  if (p.colour == ColourMode::Fibres && pipeline.fibresEmpty())
    throw GlError("the fibre colour mode needs a fibre set (setFibres)");
  view = FrameView::fromHost(v.view, v.projection, size, std::max(p.guard, 0), lo, hi, 0.5f * (lo + hi));
  const bool changed =
      still || v.depthTexture != depthTexture || v.normalTexture != normalTexture || v.viewport != viewport;
  depthTexture = v.depthTexture;
  normalTexture = v.normalTexture;
  viewport = v.viewport;
  HostSurface host;
  host.depth = v.depthTexture;
  host.normal = v.normalTexture;
  host.biasedNormals = v.normalEncoding == NormalEncoding::Biased;
  host.origin = {v.viewport.x, v.viewport.y};
  host.projection = v.projection;
  pipeline.beginTimer(FabricPipeline::kProjection);
  pipeline.projection().geometryStage().import(host, view);
  pipeline.project(view, p, lo, changed);
  return true;
}

EmbeddedFabric::EmbeddedFabric() {
  const GlStateGuard guard;
  impl_ = std::make_unique<Impl>();
}

EmbeddedFabric::~EmbeddedFabric() {
  if (!impl_) return;
  const GlStateGuard guard; // deleting bound objects unbinds them: the host's bindings are restored
  impl_.reset();
}

EmbeddedFabric::EmbeddedFabric(EmbeddedFabric&&) noexcept = default;
EmbeddedFabric& EmbeddedFabric::operator=(EmbeddedFabric&&) noexcept = default;

void EmbeddedFabric::setField(const TensorField& field) {
  const GlStateGuard guard;
  impl_->pipeline.setField(field);
}

void EmbeddedFabric::setFibres(const FibreSet& fibres, const ScalarVolume* fa) {
  const GlStateGuard guard;
  impl_->pipeline.setFibres(fibres, fa);
}

void EmbeddedFabric::clearFibres() {
  const GlStateGuard guard;
  impl_->pipeline.clearFibres();
}

void EmbeddedFabric::setBackground(const ScalarVolume* volume, float lo, float hi) {
  const GlStateGuard guard;
  impl_->pipeline.setBackground(volume, lo, hi);
}

void EmbeddedFabric::draw(const HostView& v, const FabricParams& p) {
  const GlStateGuard guard;
  if (!impl_->prepare(v, p, false)) return;
  impl_->pipeline.advect(p);
  glBindFramebuffer(GL_FRAMEBUFFER, v.framebuffer);
  impl_->pipeline.composite(impl_->view, p, {v.viewport.x, v.viewport.y}, CompositeDepth::Window);
}

void EmbeddedFabric::drawStill(const HostView& v, const FabricParams& p) {
  const GlStateGuard guard;
  if (!impl_->prepare(v, p, true)) return;
  impl_->lastIterations = impl_->pipeline.converge(p);
  glBindFramebuffer(GL_FRAMEBUFFER, v.framebuffer);
  impl_->pipeline.composite(impl_->view, p, {v.viewport.x, v.viewport.y}, CompositeDepth::Window);
}

void EmbeddedFabric::restart() {
  impl_->pipeline.invalidate();
}

void EmbeddedFabric::setTiming(bool on) {
  impl_->pipeline.setTiming(on);
}

PassTimes EmbeddedFabric::lastTimes() const {
  const GlStateGuard guard;
  return impl_->pipeline.lastTimes();
}

int EmbeddedFabric::lastIterations() const {
  return impl_->lastIterations;
}

void EmbeddedFabric::setComputePasses(bool on) {
  impl_->pipeline.setComputePasses(on);
}

} // namespace dtf::render
