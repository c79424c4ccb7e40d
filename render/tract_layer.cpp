#include "render/tract_layer.h"

#include <algorithm>
#include <cmath>

namespace dtf::render {

TractBudget::TractBudget(double targetMs, std::size_t initialSegments)
    : targetMs_(std::max(targetMs, 0.1)), segments_(std::clamp(initialSegments, kMinSegments, kMaxSegments)) {
}

void TractBudget::measured(std::size_t segments, double ms) {
  if (segments < kMinSample || !(ms > 0) || !std::isfinite(ms)) return;
  const double sample = ms / static_cast<double>(segments);
  msPerSegment_ = msPerSegment_ < 0 ? sample : 0.5 * (msPerSegment_ + sample);
  const double wanted = targetMs_ / msPerSegment_;
  const double lo = 0.5 * static_cast<double>(segments_), hi = 2.0 * static_cast<double>(segments_);
  segments_ = static_cast<std::size_t>(
      std::clamp(std::clamp(wanted, lo, hi), double(kMinSegments), double(kMaxSegments)));
}

TractLayer::TractLayer()
    : program_("common/fullscreen.vert", "tracts/layer.frag"), vao_(createVertexArray()) {
  for (auto& q : queries_)
    q = createQuery(GL_TIME_ELAPSED);
}

void TractLayer::reset() {
  valid_ = building_ = backReady_ = false;
  progress_ = 0;
}

void TractLayer::ensureSize(glm::ivec2 size) {
  if (size == size_) return;
  size_ = size;
  for (auto& t : targets_) {
    t.colour = Texture::create2D(GL_RGBA8, size.x, size.y);
    t.depth = Texture::create2D(GL_DEPTH_COMPONENT32F, size.x, size.y);
    t.colour.setFilter(GL_NEAREST, GL_NEAREST);
    t.fbo = createFramebuffer();
    attachTargets(t.fbo, {&t.colour}, &t.depth);
  }
  fabricCopy_ = Texture::create2D(GL_RGBA8, size.x, size.y);
  fabricCopy_.setFilter(GL_NEAREST, GL_NEAREST);
  copyFbo_ = createFramebuffer();
  attachTargets(copyFbo_, {&fabricCopy_}, nullptr);
  copyValid_ = false;
  reset();
}

void TractLayer::begin(Target& t, const Framebuffer& fabric) {
  const float clear[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(t.fbo.id(), GL_COLOR, 0, clear);
  glBlitNamedFramebuffer(fabric.id(), t.fbo.id(), 0, 0, size_.x, size_.y, 0, 0, size_.x, size_.y,
                         GL_DEPTH_BUFFER_BIT, GL_NEAREST);
}

void TractLayer::drawTimed(const TractRenderer& tracts, const FrameView& view, const TractStyle& style,
                           int level, std::size_t first, std::size_t count) {
  const int q = nextQuery_;
  nextQuery_ = 1 - nextQuery_;
  glBeginQuery(GL_TIME_ELAPSED, queries_[q].id());
  tracts.draw(view, style, level, first, count);
  glEndQuery(GL_TIME_ELAPSED);
  querySegments_[q] =
      std::min(count, tracts.segmentCount(level) - std::min(first, tracts.segmentCount(level)));
  queryPending_[q] = true;
}

bool TractLayer::takeTiming(std::size_t& segments, double& ms) {
  for (int i = 0; i < 2; ++i) {
    const int q = (nextQuery_ + i) % 2; // oldest first
    if (!queryPending_[q]) continue;
    GLint available = 0;
    glGetQueryObjectiv(queries_[q].id(), GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) continue;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(queries_[q].id(), GL_QUERY_RESULT, &ns);
    queryPending_[q] = false;
    segments = querySegments_[q];
    ms = static_cast<double>(ns) * 1e-6;
    return true;
  }
  return false;
}

void TractLayer::composite(const Framebuffer& fabric) {
  glBindFramebuffer(GL_FRAMEBUFFER, fabric.id());
  glViewport(0, 0, size_.x, size_.y);
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glBindTextureUnit(0, fabricCopy_.id());
  glBindTextureUnit(1, targets_[front_].colour.id());
  program_.use();
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
}

bool TractLayer::frame(const TractRenderer& tracts, const Frame& f) {
  ensureSize(f.view.viewport);
  if (f.fabricChanged || !copyValid_) {
    glBlitNamedFramebuffer(f.fabric->id(), copyFbo_.id(), 0, 0, size_.x, size_.y, 0, 0, size_.x, size_.y,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    copyValid_ = true;
  }
  bool changed = f.fabricChanged;
  const bool restart = !valid_ || f.key != key_ || f.view.viewProjViewport != viewProj_ ||
                       !(f.style == style_) || f.fabric->id() != fabricId_;
  const std::size_t total = tracts.segmentCount(0);
  if (restart) {
    key_ = f.key;
    viewProj_ = f.view.viewProjViewport;
    style_ = f.style;
    fabricId_ = f.fabric->id();
    Target& back = targets_[1 - front_];
    begin(back, *f.fabric);
    const auto [level, count] = tracts.levelFor(f.budget);
    glBindFramebuffer(GL_FRAMEBUFFER, back.fbo.id());
    drawTimed(tracts, f.view, f.style, level, 0, count);
    front_ = 1 - front_;
    shownLevel_ = level;
    shownSegments_ = std::min(count, tracts.segmentCount(level));
    building_ = !(level == 0 && count >= total);
    backReady_ = false;
    progress_ = 0;
    valid_ = true;
    changed = true;
  } else if (building_ && !f.moving) {
    Target& back = targets_[1 - front_];
    if (!backReady_) {
      begin(back, *f.fabric);
      backReady_ = true;
      progress_ = 0;
    }
    const std::size_t n = std::max<std::size_t>(f.budget, 1);
    glBindFramebuffer(GL_FRAMEBUFFER, back.fbo.id());
    drawTimed(tracts, f.view, f.style, 0, progress_, n);
    progress_ += n;
    if (progress_ >= total) {
      front_ = 1 - front_;
      shownLevel_ = 0;
      shownSegments_ = total;
      building_ = backReady_ = false;
      changed = true;
    }
  }
  if (changed) composite(*f.fabric);
  return changed;
}

} // namespace dtf::render
