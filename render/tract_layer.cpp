// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/tract_layer.h"

#include "render/gl_state.h"
#include "render/program_bindings.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace dtf::render {

TractBudget::TractBudget(double targetMs) : targetMs_(std::max(targetMs, 0.1)) {
  cost_.fill(-1.0);
}

void TractBudget::measured(int level, std::size_t segments, double ms) {
  if (level < 0 || level >= kMaxLevels || segments < kMinSample || !(ms > 0) || !std::isfinite(ms)) return;
  const double sample = ms / static_cast<double>(segments);
  double& c = cost_[static_cast<std::size_t>(level)];
  c = c < 0 ? sample : 0.5 * (c + sample);
}

double TractBudget::msPerSegment(int level) const {
  level = std::clamp(level, 0, kMaxLevels - 1);
  for (int d = 0; d < kMaxLevels; ++d) // the nearest measured level, the coarser one first on a tie
    for (int k : {level + d, level - d})
      if (k >= 0 && k < kMaxLevels && cost_[static_cast<std::size_t>(k)] > 0)
        return cost_[static_cast<std::size_t>(k)];
  return kInitialMsPerSegment;
}

TractBudget::Choice TractBudget::choose(const TractRenderer& tracts) const {
  std::array<std::size_t, kMaxLevels> counts{};
  const int levels = std::min(tracts.levelCount(), kMaxLevels);
  for (int k = 0; k < levels; ++k)
    counts[static_cast<std::size_t>(k)] = tracts.segmentCount(k);
  return choose(std::span<const std::size_t>(counts.data(), static_cast<std::size_t>(levels)));
}

TractBudget::Choice TractBudget::choose(std::span<const std::size_t> count) const {
  const int levels = static_cast<int>(std::min<std::size_t>(count.size(), kMaxLevels));
  if (levels == 0) return {0, 0};
  for (int k = 0; k < levels; ++k)
    if (static_cast<double>(count[static_cast<std::size_t>(k)]) * msPerSegment(k) <= targetMs_)
      return {k, count[static_cast<std::size_t>(k)]};
  Choice best{levels - 1, kMinSegments};
  double bestShare = -1;
  for (int k = 0; k < levels; ++k) {
    const double fit = targetMs_ / msPerSegment(k);
    const double share =
        fit / static_cast<double>(std::max<std::size_t>(count[static_cast<std::size_t>(k)], 1));
    if (share > bestShare * 1.05) { // a coarser level must show clearly more of the lines to win
      bestShare = share;
      best = {k, std::max(static_cast<std::size_t>(fit), kMinSegments)};
    }
  }
  return best;
}

std::size_t TractBudget::chunk() const {
  return std::max(static_cast<std::size_t>(targetMs_ / msPerSegment(0)), kMinSegments);
}

TractLayer::TractLayer()
    : program_("common/fullscreen.vert", "tracts/layer.frag", programDefines<TractLayerProgram>()),
      vao_(createVertexArray()) {
  for (auto& q : queries_)
    q = createQuery(GL_TIME_ELAPSED);
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (renderer && (std::strstr(renderer, "llvmpipe") || std::strstr(renderer, "softpipe") ||
                   std::strstr(renderer, "swrast")))
    timing_ = Timing::Finish;
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
  const std::size_t available = tracts.segmentCount(level);
  querySegments_[q] = std::min(count, available - std::min(first, available));
  queryLevel_[q] = level;
  queryPending_[q] = true;
  if (timing_ == Timing::Finish) {
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    tracts.draw(view, style, level, first, count);
    glFinish();
    finishMs_[q] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return;
  }
  glBeginQuery(GL_TIME_ELAPSED, queries_[q].id());
  tracts.draw(view, style, level, first, count);
  glEndQuery(GL_TIME_ELAPSED);
}

bool TractLayer::takeTiming(int& level, std::size_t& segments, double& ms) {
  for (int i = 0; i < 2; ++i) {
    const int q = (nextQuery_ + i) % 2; // oldest first
    if (!queryPending_[q]) continue;
    if (timing_ == Timing::Finish) {
      ms = finishMs_[q];
    } else {
      GLint available = 0;
      glGetQueryObjectiv(queries_[q].id(), GL_QUERY_RESULT_AVAILABLE, &available);
      if (!available) continue;
      GLuint64 ns = 0;
      glGetQueryObjectui64v(queries_[q].id(), GL_QUERY_RESULT, &ns);
      ms = static_cast<double>(ns) * 1e-6;
    }
    queryPending_[q] = false;
    level = queryLevel_[q];
    segments = querySegments_[q];
    return true;
  }
  return false;
}

void TractLayer::composite(const Framebuffer& fabric) {
  glBindFramebuffer(GL_FRAMEBUFFER, fabric.id());
  glViewport(0, 0, size_.x, size_.y);
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  bindTexture(TractLayerProgram::Unit::Fabric, fabricCopy_.id());
  bindTexture(TractLayerProgram::Unit::Layer, targets_[front_].colour.id());
  program_.use();
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
}

bool TractLayer::frame(const TractRenderer& tracts, const Frame& f) {
  const GlStateGuard guard;
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
    const int level = std::clamp(f.draw.level, 0, std::max(tracts.levelCount() - 1, 0));
    const std::size_t count = f.draw.segments;
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
    const std::size_t n = std::max<std::size_t>(f.chunk, 1);
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
