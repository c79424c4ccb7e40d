// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/tract_renderer.h"

#include "io/model/error.h"
#include "render/gl_state.h"
#include "render/program_bindings.h"
#include "render/shader_program.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

namespace dtf::render {

namespace {

// Points kept from a line of n >= 2 points with step `step` (first, every step-th, last).
std::size_t keptPoints(std::size_t n, std::size_t step) {
  return (n - 2) / step + 2;
}

// 0 .. n-1 in bit-reversed order of a power-of-two range: every prefix is spread evenly over 0 .. n-1.
std::vector<std::uint32_t> stratifiedOrder(std::size_t n) {
  std::vector<std::uint32_t> order;
  order.reserve(n);
  int bits = 0;
  while ((std::size_t(1) << bits) < n)
    ++bits;
  for (std::size_t i = 0; i < (std::size_t(1) << bits); ++i) {
    std::size_t r = 0;
    for (int b = 0; b < bits; ++b)
      if (i & (std::size_t(1) << b)) r |= std::size_t(1) << (bits - 1 - b);
    if (r < n) order.push_back(static_cast<std::uint32_t>(r));
  }
  return order;
}

} // namespace

glm::vec3 tractValueColour(float t) {
  static const glm::vec3 anchors[5] = {{0x44 / 255.0f, 0x01 / 255.0f, 0x54 / 255.0f},
                                       {0x3b / 255.0f, 0x52 / 255.0f, 0x8b / 255.0f},
                                       {0x21 / 255.0f, 0x91 / 255.0f, 0x8c / 255.0f},
                                       {0x5e / 255.0f, 0xc9 / 255.0f, 0x62 / 255.0f},
                                       {0xfd / 255.0f, 0xe7 / 255.0f, 0x25 / 255.0f}};
  if (!(t >= 0)) t = 0; // NaN too
  t = std::min(t, 1.0f) * 4.0f;
  const int i = std::min(static_cast<int>(t), 3);
  return glm::mix(anchors[i], anchors[i + 1], t - static_cast<float>(i));
}

namespace {

// Output points from which decimate() copies positions-only lines on two threads.
constexpr std::size_t kParallelDecimation = 200'000;

// decimateForDisplay over the lines `keep` lists (ascending; null: every line).
Polylines decimate(const Polylines& lines, const std::vector<std::uint32_t>* keep, std::size_t maxPoints,
                   std::size_t minLinePoints) {
  Polylines out;
  out.offsets.push_back(0);
  const std::size_t candidates = keep ? keep->size() : lines.lineCount();
  auto lineAt = [&](std::size_t k) -> std::uint32_t {
    return keep ? (*keep)[k] : static_cast<std::uint32_t>(k);
  };
  auto sizeOf = [&](std::uint32_t l) -> std::size_t {
    return l < lines.lineCount() ? lines.offsets[l + 1] - lines.offsets[l] : 0;
  };
  std::size_t longest = 0, shapePoints = 0, drawableLines = 0;
  for (std::size_t k = 0; k < candidates; ++k) {
    const std::size_t n = sizeOf(lineAt(k));
    if (n >= 2) shapePoints += std::min(n, std::max<std::size_t>(minLinePoints, 2)), ++drawableLines;
    longest = std::max(longest, n);
  }
  for (const auto& d : lines.perLine)
    out.perLine.push_back({d.name, d.components, {}});
  if (shapePoints == 0 || maxPoints < 2) return out;
  // Every m-th drawable line when the lines at minLinePoints points each exceed the cap. The second
  // bound makes two points per kept line always fit, however the line lengths are spread.
  const std::size_t pairs = maxPoints / 2;
  const std::size_t lineStep =
      std::max((shapePoints + maxPoints - 1) / maxPoints, (drawableLines + pairs - 1) / pairs);
  std::vector<std::uint32_t> kept, keptSize; // source line of each output line (ascending when `keep` is)
  kept.reserve(drawableLines / lineStep + 1);
  keptSize.reserve(drawableLines / lineStep + 1);
  std::size_t drawable = 0;
  for (std::size_t k = 0; k < candidates; ++k) {
    const std::uint32_t l = lineAt(k);
    const std::size_t n = sizeOf(l);
    if (n >= 2 && drawable++ % lineStep == 0) {
      kept.push_back(l);
      keptSize.push_back(static_cast<std::uint32_t>(n));
    }
  }
  auto total = [&](std::size_t step) {
    std::size_t sum = 0;
    for (std::uint32_t n : keptSize)
      sum += keptPoints(n, step);
    return sum;
  };
  // total() does not increase with the step: the smallest step that fits, by bisection.
  std::size_t lo = 1, hi = std::max<std::size_t>(longest, 1);
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (total(mid) <= maxPoints)
      hi = mid;
    else
      lo = mid + 1;
  }
  const std::size_t step = lo;
  const std::size_t count = total(step);
  if (lines.perPoint.empty()) {
    // Positions only (a whole-brain tractogram's usual case): each kept line's place in the output is known
    // from its size, so large outputs are copied on two threads; the copy reads the positions at random.
    out.offsets.resize(kept.size() + 1);
    for (std::size_t k = 0; k < kept.size(); ++k)
      out.offsets[k + 1] = out.offsets[k] + static_cast<std::uint32_t>(keptPoints(keptSize[k], step));
    out.points.resize(count);
    glm::vec3* dst = out.points.data();
    auto copy = [&](std::size_t from, std::size_t to) {
      for (std::size_t k = from; k < to; ++k) {
        const glm::vec3* src = lines.points.data() + lines.offsets[kept[k]];
        glm::vec3* o = dst + out.offsets[k];
        const std::size_t n = keptSize[k];
        for (std::size_t i = 0; i < n - 1; i += step)
          *o++ = src[i];
        *o = src[n - 1];
      }
    };
    if (count >= kParallelDecimation) {
      std::thread helper(copy, kept.size() / 2, kept.size());
      copy(0, kept.size() / 2);
      helper.join();
    } else {
      copy(0, kept.size());
    }
  } else {
    out.points.reserve(count);
    out.offsets.reserve(kept.size() + 1);
    for (const auto& d : lines.perPoint) {
      out.perPoint.push_back({d.name, d.components, {}});
      out.perPoint.back().values.reserve(count * static_cast<std::size_t>(d.components));
    }
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const std::size_t b = lines.offsets[kept[k]], n = keptSize[k];
      if (step == 1) {
        out.appendPoints(lines, b, b + n);
      } else {
        for (std::size_t i = 0; i < n - 1; i += step)
          out.appendPoints(lines, b + i, b + i + 1);
        out.appendPoints(lines, b + n - 1, b + n);
      }
      out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
    }
  }
  for (std::uint32_t l : kept)
    for (std::size_t a = 0; a < lines.perLine.size(); ++a) {
      const auto c = static_cast<std::size_t>(lines.perLine[a].components);
      const auto first = lines.perLine[a].values.begin() + static_cast<std::ptrdiff_t>(l * c);
      out.perLine[a].values.insert(out.perLine[a].values.end(), first, first + static_cast<std::ptrdiff_t>(c));
    }
  // `kept` ascends when `keep` does: each group's members by binary search.
  for (const TractGroup& g : lines.groups) {
    TractGroup ng;
    ng.name = g.name;
    for (std::uint32_t i : g.lines) {
      const auto it = std::lower_bound(kept.begin(), kept.end(), i);
      if (it != kept.end() && *it == i) ng.lines.push_back(static_cast<std::uint32_t>(it - kept.begin()));
    }
    std::sort(ng.lines.begin(), ng.lines.end());
    out.groups.push_back(std::move(ng));
  }
  return out;
}

} // namespace

Polylines decimateForDisplay(const Polylines& lines, std::size_t maxPoints) {
  return decimate(lines, nullptr, maxPoints, kMinDisplayLinePoints);
}

Polylines decimateForDisplay(const Polylines& lines, const std::vector<std::uint32_t>& keep,
                             std::size_t maxPoints, std::size_t minLinePoints) {
  return decimate(lines, &keep, maxPoints, minLinePoints);
}

DisplayTracts prepareDisplayTracts(const Polylines& lines, std::size_t maxPoints, int maxLevels) {
  Polylines shown = decimateForDisplay(lines, maxPoints);
  DisplayTracts d;
  d.points = shown.points.take();
  d.lines = shown.lineCount();
  for (const auto& a : shown.perPoint)
    if (a.name == kTractDisplayColours && a.components == 4 && a.values.size() == 4 * d.points.size()) {
      d.colours.resize(d.points.size());
      for (std::size_t i = 0; i < d.points.size(); ++i)
        for (int c = 0; c < 4; ++c)
          d.colours[i][c] = static_cast<std::uint8_t>(
              std::lround(std::clamp(a.values[4 * i + static_cast<std::size_t>(c)], 0.0f, 1.0f) * 255.0f));
    }
  for (const auto& a : shown.perPoint)
    if (a.name == kTractDisplayNode && a.components == 1 && a.values.size() == d.points.size()) {
      d.nodes.resize(d.points.size());
      for (std::size_t i = 0; i < d.points.size(); ++i)
        d.nodes[i] = std::isfinite(a.values[i]) && a.values[i] >= 0 ? a.values[i] : -1.0f;
    }
  if (d.lines == 0) return d;
  const std::vector<std::uint32_t> order = stratifiedOrder(d.lines);
  std::size_t previous = 0;
  for (int k = 0; k < std::max(maxLevels, 1); ++k) {
    const std::uint32_t step = 1u << k;
    const std::size_t start = d.segments.size();
    for (std::uint32_t l : order) {
      const std::uint32_t b = shown.offsets[l], last = shown.offsets[l + 1] - 1;
      std::uint32_t from = b;
      for (std::uint32_t i = b + step; i < last; i += step) {
        d.segments.push_back(from);
        d.segments.push_back(i);
        from = i;
      }
      d.segments.push_back(from);
      d.segments.push_back(last);
    }
    const std::size_t count = (d.segments.size() - start) / 2;
    if (k > 0 && 4 * count > 3 * previous) { // not worth a level: lines are already short
      d.segments.resize(start);
      break;
    }
    d.levelOffsets.push_back(d.segments.size() / 2);
    previous = count;
  }
  return d;
}

TractRenderer::TractRenderer()
    : program_({{GL_VERTEX_SHADER, "tracts/lines.vert"},
                {GL_GEOMETRY_SHADER, "tracts/lines.geom"},
                {GL_FRAGMENT_SHADER, "tracts/lines.frag"}},
               programDefines<TractLinesProgram>(), uniformNames<TractLinesProgram::Uniform>()),
      vao_(createVertexArray()) {}

void TractRenderer::setTracts(const Polylines& lines, std::size_t maxPoints) {
  upload(prepareDisplayTracts(lines, maxPoints));
}

namespace {

// Puts `bytes` of `data` at the start of `buffer`, reusing its storage when `capacity` holds them (a region
// change uploads a new selection of about the same size: no new allocation, no page faults on first touch);
// else a new buffer with a quarter more room. Returns false when the GL is out of memory.
bool fill(Buffer& buffer, std::size_t& capacity, const void* data, std::size_t bytes) {
  if (!buffer.id() || bytes > capacity) {
    buffer = createBuffer();
    capacity = std::max<std::size_t>(bytes + bytes / 4, 4096);
    glNamedBufferStorage(buffer.id(), static_cast<GLsizeiptr>(capacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
    if (glGetError() == GL_OUT_OF_MEMORY) {
      buffer = Buffer();
      capacity = 0;
      return false;
    }
  }
  if (bytes) glNamedBufferSubData(buffer.id(), 0, static_cast<GLsizeiptr>(bytes), data);
  return true;
}

} // namespace

void TractRenderer::upload(const DisplayTracts& t) {
  levelOffsets_.assign(1, 0);
  pointCount_ = lineCount_ = 0;
  hasNodes_ = false;
  if (t.points.empty() || t.segments.empty()) return;
  if (!fill(points_, pointsCapacity_, t.points.data(), t.points.size() * sizeof(glm::vec3)) ||
      !fill(segments_, segmentsCapacity_, t.segments.data(), t.segments.size() * sizeof(std::uint32_t))) {
    points_ = Buffer();
    segments_ = Buffer();
    pointsCapacity_ = segmentsCapacity_ = 0;
    throw GlError("out of GPU memory for " + std::to_string(t.points.size()) + " tract points");
  }
  glVertexArrayVertexBuffer(vao_.id(), 0, points_.id(), 0, sizeof(glm::vec3));
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
  glVertexArrayElementBuffer(vao_.id(), segments_.id());
  if (t.colours.size() == t.points.size() &&
      fill(colours_, coloursCapacity_, t.colours.data(), t.colours.size() * sizeof(glm::u8vec4))) {
    glVertexArrayVertexBuffer(vao_.id(), 1, colours_.id(), 0, sizeof(glm::u8vec4));
    glEnableVertexArrayAttrib(vao_.id(), 1);
    glVertexArrayAttribFormat(vao_.id(), 1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0);
    glVertexArrayAttribBinding(vao_.id(), 1, 1);
  } else {
    glDisableVertexArrayAttrib(vao_.id(), 1);
  }
  hasNodes_ = t.nodes.size() == t.points.size() &&
              fill(nodes_, nodesCapacity_, t.nodes.data(), t.nodes.size() * sizeof(float));
  if (hasNodes_) {
    glVertexArrayVertexBuffer(vao_.id(), 2, nodes_.id(), 0, sizeof(float));
    glEnableVertexArrayAttrib(vao_.id(), 2);
    glVertexArrayAttribFormat(vao_.id(), 2, 1, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_.id(), 2, 2);
  } else {
    glDisableVertexArrayAttrib(vao_.id(), 2);
  }
  levelOffsets_ = t.levelOffsets;
  pointCount_ = t.points.size();
  lineCount_ = t.lines;
}

void TractRenderer::setNodeColours(std::span<const glm::vec4> colours) {
  if (colours.size() > kMaxTractNodeColours)
    throw UsageError("at most " + std::to_string(kMaxTractNodeColours) + " node colours, not " +
                     std::to_string(colours.size()));
  using U = TractLinesProgram::Uniform;
  program_.set(U::NodeColoured, !colours.empty());
  const GLint at = program_.location(U::NodeColours);
  if (!colours.empty() && at >= 0)
    glProgramUniform4fv(program_.id(), at, static_cast<GLsizei>(colours.size()), &colours[0].x);
}

std::size_t TractRenderer::segmentCount(int level) const {
  if (level < 0 || level >= levelCount()) return 0;
  return levelOffsets_[static_cast<std::size_t>(level) + 1] - levelOffsets_[static_cast<std::size_t>(level)];
}

void TractRenderer::draw(const FrameView& view, const TractStyle& style) const {
  draw(view, style, 0, 0, segmentCount(0));
}

void TractRenderer::draw(const FrameView& view, const TractStyle& style, int level, std::size_t first,
                         std::size_t count) const {
  const std::size_t available = segmentCount(level);
  if (first >= available || count == 0) return;
  const GlStateGuard guard;
  count = std::min(count, available - first);
  // FrameView keeps world -> clip of the viewport and world -> eye; the projection is their quotient.
  const glm::mat4 proj = view.viewProjViewport * glm::inverse(view.view);
  using U = TractLinesProgram::Uniform;
  program_.set(U::View, view.view);
  program_.set(U::Proj, proj);
  program_.set(U::ViewRot, view.viewRot);
  program_.set(U::Viewport, glm::vec2(view.viewport));
  program_.set(U::WidthPx, std::max(style.widthPx, 0.5f));
  program_.set(U::DepthBiasMm, style.depthBiasMm);
  program_.set(U::Plane, style.plane);
  program_.set(U::SlabMm, style.slabMm);
  program_.set(U::HighlightNode, style.highlightNode);
  program_.set(U::HighlightHalfWidth, std::max(style.highlightHalfWidth, 0));
  program_.set(U::HighlightColour, style.highlightColour);
  program_.use();
  glViewport(0, 0, view.viewport.x, view.viewport.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(vao_.id());
  glVertexAttrib4f(1, 0, 0, 0, 0); // DEC where no colour array is bound
  glVertexAttrib1f(2, -1.0f);      // no node where no node array is bound
  // GL_LINES over the element buffer of point index pairs; the geometry shader widens each segment.
  const std::size_t start = levelOffsets_[static_cast<std::size_t>(level)] + first;
  glDrawElements(GL_LINES, static_cast<GLsizei>(2 * count), GL_UNSIGNED_INT,
                 reinterpret_cast<const void*>(start * 2 * sizeof(std::uint32_t)));
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
