#include "render/tract_renderer.h"

#include "io/model/error.h"
#include "render/shader_program.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstring>
#include <string>

namespace dtf::render {

namespace {

// Points kept from a line of n >= 2 points with step `step` (first, every step-th, last).
std::size_t keptPoints(std::size_t n, std::size_t step) { return (n - 2) / step + 2; }

} // namespace

Polylines decimateForDisplay(const Polylines& lines, std::size_t maxPoints) {
  Polylines out;
  const std::size_t count = lines.lineCount();
  std::size_t drawable = 0, longest = 0;
  for (std::size_t l = 0; l < count; ++l) {
    const std::size_t n = lines.offsets[l + 1] - lines.offsets[l];
    if (n >= 2) ++drawable;
    longest = std::max(longest, n);
  }
  out.offsets.push_back(0);
  if (drawable == 0 || maxPoints < 2) return out;
  // Every m-th drawable line when even two points per line exceed the cap.
  const std::size_t pairs = maxPoints / 2;
  const std::size_t lineStep = (drawable + pairs - 1) / pairs;
  auto total = [&](std::size_t step) {
    std::size_t sum = 0, k = 0;
    for (std::size_t l = 0; l < count; ++l) {
      const std::size_t n = lines.offsets[l + 1] - lines.offsets[l];
      if (n < 2) continue;
      if (k++ % lineStep == 0) sum += keptPoints(n, step);
    }
    return sum;
  };
  // total() does not increase with the step: the smallest step that fits, by bisection.
  std::size_t lo = 1, hi = std::max<std::size_t>(longest, 1);
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (total(mid) <= maxPoints) hi = mid;
    else lo = mid + 1;
  }
  const std::size_t step = lo;
  out.points.reserve(total(step));
  out.offsets.reserve(drawable / lineStep + 2);
  std::size_t k = 0;
  for (std::size_t l = 0; l < count; ++l) {
    const std::size_t b = lines.offsets[l], n = lines.offsets[l + 1] - b;
    if (n < 2 || k++ % lineStep != 0) continue;
    for (std::size_t i = 0; i < n - 1; i += step) out.points.push_back(lines.points[b + i]);
    out.points.push_back(lines.points[b + n - 1]);
    out.offsets.push_back(static_cast<std::uint32_t>(out.points.size()));
  }
  return out;
}

TractRenderer::TractRenderer() : vao_(createVertexArray()) {
  GLuint stages[3] = {compileShaderStage(GL_VERTEX_SHADER, "tracts/lines.vert"), 0, 0};
  try {
    stages[1] = compileShaderStage(GL_GEOMETRY_SHADER, "tracts/lines.geom");
    stages[2] = compileShaderStage(GL_FRAGMENT_SHADER, "tracts/lines.frag");
  } catch (...) {
    for (GLuint s : stages)
      if (s) glDeleteShader(s);
    throw;
  }
  program_ = ProgramHandle(glCreateProgram());
  for (GLuint s : stages) glAttachShader(program_.id(), s);
  glLinkProgram(program_.id());
  for (GLuint s : stages) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program_.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(program_.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
    glGetProgramInfoLog(program_.id(), len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    throw GlError("linking tracts/lines.{vert,geom,frag} failed:\n" + log);
  }
  const GLuint p = program_.id();
  uView_ = glGetUniformLocation(p, "u_view");
  uProj_ = glGetUniformLocation(p, "u_proj");
  uViewRot_ = glGetUniformLocation(p, "u_viewRot");
  uViewport_ = glGetUniformLocation(p, "u_viewport");
  uWidth_ = glGetUniformLocation(p, "u_widthPx");
  uBias_ = glGetUniformLocation(p, "u_depthBiasMm");
  uPlane_ = glGetUniformLocation(p, "u_plane");
  uSlab_ = glGetUniformLocation(p, "u_slabMm");
}

void TractRenderer::setTracts(const Polylines& lines, std::size_t maxPoints) {
  Polylines shown = decimateForDisplay(lines, maxPoints);
  firsts_.clear();
  counts_.clear();
  pointCount_ = shown.points.size();
  points_ = Buffer();
  if (pointCount_ == 0) return;
  firsts_.reserve(shown.lineCount());
  counts_.reserve(shown.lineCount());
  for (std::size_t l = 0; l < shown.lineCount(); ++l) {
    firsts_.push_back(static_cast<GLint>(shown.offsets[l]));
    counts_.push_back(static_cast<GLsizei>(shown.offsets[l + 1] - shown.offsets[l]));
  }
  points_ = createBuffer();
  glNamedBufferStorage(points_.id(), static_cast<GLsizeiptr>(pointCount_ * sizeof(glm::vec3)),
                       shown.points.data(), 0);
  glVertexArrayVertexBuffer(vao_.id(), 0, points_.id(), 0, sizeof(glm::vec3));
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
}

void TractRenderer::draw(const FrameView& view, const TractStyle& style) const {
  if (counts_.empty()) return;
  // FrameView keeps world -> clip of the viewport and world -> eye; the projection is their quotient.
  const glm::mat4 proj = view.viewProjViewport * glm::inverse(view.view);
  const GLuint p = program_.id();
  glProgramUniformMatrix4fv(p, uView_, 1, GL_FALSE, glm::value_ptr(view.view));
  glProgramUniformMatrix4fv(p, uProj_, 1, GL_FALSE, glm::value_ptr(proj));
  glProgramUniformMatrix3fv(p, uViewRot_, 1, GL_FALSE, glm::value_ptr(view.viewRot));
  glProgramUniform2f(p, uViewport_, float(view.viewport.x), float(view.viewport.y));
  glProgramUniform1f(p, uWidth_, std::max(style.widthPx, 0.5f));
  glProgramUniform1f(p, uBias_, style.depthBiasMm);
  glProgramUniform4f(p, uPlane_, style.plane.x, style.plane.y, style.plane.z, style.plane.w);
  glProgramUniform1f(p, uSlab_, style.slabMm);
  glUseProgram(p);
  glViewport(0, 0, view.viewport.x, view.viewport.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(vao_.id());
  glMultiDrawArrays(GL_LINE_STRIP, firsts_.data(), counts_.data(), static_cast<GLsizei>(counts_.size()));
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

} // namespace dtf::render
