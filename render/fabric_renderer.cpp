// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric_renderer.h"

#include "io/model/error.h"
#include "render/gl_state.h"

#include <algorithm>
#include <cstring>

namespace dtf::render {

FabricRenderer::FabricRenderer() = default;

FabricRenderer::~FabricRenderer() = default;

void FabricRenderer::setMesh(const Mesh& mesh) {
  mesh_.upload(mesh);
  pipeline_.invalidate();
}

void FabricRenderer::setField(const TensorField& field) {
  pipeline_.setField(field);
}

void FabricRenderer::setFibres(const FibreSet& fibres, const ScalarVolume* fa) {
  pipeline_.setFibres(fibres, fa);
}

void FabricRenderer::clearFibres() {
  pipeline_.clearFibres();
}

void FabricRenderer::setUncertainty(const ScalarVolume* cone) { pipeline_.setUncertainty(cone); }
void FabricRenderer::setAlong(const ScalarVolume* weight) {
  pipeline_.setAlong(weight);
}

void FabricRenderer::setBackground(const ScalarVolume* volume, float lo, float hi) {
  pipeline_.setBackground(volume, lo, hi);
}

void FabricRenderer::resize(int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw GlError("render size " + std::to_string(width) + "x" + std::to_string(height) + " out of range");
  if (glm::ivec2(width, height) == size_) return;
  size_ = {width, height};
  outColour_ = Texture::create2D(GL_RGBA8, width, height);
  outDepth_ = Texture::create2D(GL_DEPTH_COMPONENT32F, width, height);
  output_ = createFramebuffer();
  attachTargets(output_, {&outColour_}, &outDepth_);
  compositeDepth_ = Texture::create2D(GL_DEPTH_COMPONENT32F, width, height);
  depthFbo_ = createFramebuffer();
  attachTargets(depthFbo_, {}, &compositeDepth_);
  depthProjection_ = 0;
  pipeline_.invalidate();
}

double FabricRenderer::effectiveLod(const FrameView& view, const FabricParams& p) const {
  return pipeline_.effectiveLod(view, p);
}

void FabricRenderer::prepare(const Camera& camera, const FabricParams& p) {
  if (size_.x < 1) throw GlError("FabricRenderer: resize() before rendering");
  pipeline_.clearTimers();
  view_ = FrameView::make(camera, size_, std::max(p.guard, 0), mesh_.boundsLo(), mesh_.boundsHi());
  const bool moving = view_.viewProjViewport != lastCameraViewProj_;
  lastCameraViewProj_ = view_.viewProjViewport;
  if (moving && !still_ && p.movingScale < 1.0)
    view_ = FrameView::make(camera, size_, std::max(p.guard, 0), mesh_.boundsLo(), mesh_.boundsHi(),
                            static_cast<float>(p.movingScale));
  if (p.colour == ColourMode::Fibres && pipeline_.fibresEmpty())
    throw GlError("the fibre colour mode needs a fibre set (setFibres)");
  // A still camera over unchanged data and parameters: the geometry buffers, the tensor stage's targets and
  // the silhouettes of the last frame are the ones this frame would write.
  if (!still_ && pipeline_.projectionCurrent(view_, p)) {
    pipeline_.reuseProjection();
    return;
  }
  glm::vec3 lo, hi;
  const bool haveData = pipeline_.dataBounds(lo, hi);
  pipeline_.beginTimer(FabricPipeline::kProjection);
  ProjectionSettings ps;
  pipeline_.projection().geometryStage().run(mesh_, view_, ps.cullHidden && view_.boundsInFront, haveData);
  // The noise origin falls back to the mesh's corner only when there is no data (nothing is textured then).
  pipeline_.project(view_, p, mesh_.boundsLo());
}

void FabricRenderer::advectAndComposite(const FabricParams& p) {
  lastFused_ = fuse_ && pipeline_.fusesComposite(view_, p);
  if (!lastFused_) {
    pipeline_.advect(p);
    composite(p);
    return;
  }
  if (fusedColour_.width() != view_.target.x || fusedColour_.height() != view_.target.y) {
    fusedColour_ = Texture::create2D(GL_RGBA8, view_.target.x, view_.target.y);
    fusedProjection_ = 0;
  }
  if (fusedProjection_ != pipeline_.projections() || fusedBackground_ != p.background) {
    const float bg[4] = {p.background.x, p.background.y, p.background.z, 1.0f};
    glClearTexImage(fusedColour_.id(), 0, GL_RGBA, GL_FLOAT, bg);
    fusedProjection_ = pipeline_.projections();
    fusedBackground_ = p.background;
  }
  pipeline_.advectComposing(view_, p, fusedColour_);
  glCopyImageSubData(fusedColour_.id(), GL_TEXTURE_2D, 0, view_.guard, view_.guard, 0, outColour_.id(),
                     GL_TEXTURE_2D, 0, 0, 0, 0, size_.x, size_.y, 1);
  presentDepth();
}

void FabricRenderer::presentDepth() {
  const float one = 1.0f;
  if (depthProjection_ != pipeline_.projections()) {
    glBindFramebuffer(GL_FRAMEBUFFER, depthFbo_.id());
    glClearNamedFramebufferfv(depthFbo_.id(), GL_DEPTH, 0, &one);
    pipeline_.compositeDepth(view_);
    depthProjection_ = pipeline_.projections();
  }
  glCopyImageSubData(compositeDepth_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, outDepth_.id(), GL_TEXTURE_2D, 0, 0, 0,
                     0, size_.x, size_.y, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, output_.id());
}

void FabricRenderer::composite(const FabricParams& p) {
  // The output is cleared to the background here, so the composite lays the data's edge over that colour
  // in the shader (CompositeSettings::overClear) instead of blending.
  glBindFramebuffer(GL_FRAMEBUFFER, output_.id());
  const float bg[4] = {p.background.x, p.background.y, p.background.z, 1.0f};
  glClearNamedFramebufferfv(output_.id(), GL_COLOR, 0, bg);
  const float one = 1.0f;
  if (view_.internal != size_) { // lower resolution while moving
    glClearNamedFramebufferfv(output_.id(), GL_DEPTH, 0, &one);
    pipeline_.composite(view_, p, glm::ivec2(0), CompositeDepth::Computed, true);
    return;
  }
  // The depth the composite would write, drawn once per projection: with it in place the composite shades
  // only the pixels it draws (the early depth test), where the other blocks of pixels would cost a software
  // rasteriser the whole shader.
  presentDepth();
  pipeline_.composite(view_, p, glm::ivec2(0), CompositeDepth::Present, true);
}

void FabricRenderer::renderFrame(const Camera& camera, const FabricParams& p) {
  const GlStateGuard guard;
  prepare(camera, p);
  advectAndComposite(p);
}

Image FabricRenderer::renderStill(const Camera& camera, const FabricParams& p) {
  const GlStateGuard guard;
  pipeline_.invalidate(); // a still always starts from beta: same arguments, same image
  still_ = true;
  try {
    prepare(camera, p);
  } catch (...) {
    still_ = false;
    throw;
  }
  still_ = false;
  lastIterations_ = pipeline_.converge(p);
  composite(p);
  return readback();
}

void FabricRenderer::renderMovieFrame(const Camera& camera, const FabricParams& p, bool firstAsked) {
  const GlStateGuard guard;
  // Three thread fields (three-population fibre sets) are not reprojected: each frame converges from the
  // noise, which is anchored to world space, so consecutive frames stay coherent (at a still's cost).
  const bool first = firstAsked || !pipeline_.reprojects(p);
  if (first)
    pipeline_.invalidate();
  else
    pipeline_.reprojectNext();
  still_ = true; // full resolution
  try {
    prepare(camera, p);
  } catch (...) {
    still_ = false;
    throw;
  }
  still_ = false;
  if (first) {
    lastIterations_ = pipeline_.converge(p);
    composite(p);
  } else {
    advectAndComposite(p);
  }
  pipeline_.keepHistory(view_);
}

void FabricRenderer::renderPhong(const Camera& camera, const glm::vec3& colour) {
  const GlStateGuard guard;
  if (size_.x < 1) throw GlError("FabricRenderer: resize() before rendering");
  pipeline_.clearTimers();
  view_ = FrameView::make(camera, size_, 0, mesh_.boundsLo(), mesh_.boundsHi());
  glBindFramebuffer(GL_FRAMEBUFFER, output_.id());
  const float bg[4] = {0, 0, 0, 1};
  glClearNamedFramebufferfv(output_.id(), GL_COLOR, 0, bg);
  const float one = 1.0f;
  glClearNamedFramebufferfv(output_.id(), GL_DEPTH, 0, &one);
  pipeline_.beginTimer(FabricPipeline::kPhong);
  phong_.run(mesh_, view_, colour);
  pipeline_.endTimer();
  pipeline_.invalidate(); // the fabric targets were not updated for this camera
}

Image FabricRenderer::readback() const {
  const GlStateGuard guard;
  Image img(size_.x, size_.y);
  std::vector<std::uint8_t> rows(img.rgba.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(outColour_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rows.size()),
                    rows.data());
  const std::size_t stride = static_cast<std::size_t>(size_.x) * 4;
  for (int y = 0; y < size_.y; ++y)
    std::memcpy(&img.rgba[static_cast<std::size_t>(y) * stride],
                &rows[static_cast<std::size_t>(size_.y - 1 - y) * stride], stride);
  return img;
}

PassTimes FabricRenderer::lastTimes() const {
  return pipeline_.lastTimes();
}

unsigned FabricRenderer::coveredPixels() const {
  return pipeline_.projection().coveredPixels();
}

} // namespace dtf::render
