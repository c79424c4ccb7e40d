#include "render/fabric/advection_pass.h"

namespace dtf::render {

AdvectionPass::AdvectionPass()
    : program_("common/fullscreen.vert", "fabric/advection.frag"), vao_(createVertexArray()),
      counter_(createBuffer()) {
  const GLuint zero = 0;
  glNamedBufferStorage(counter_.id(), sizeof(GLuint), &zero, GL_DYNAMIC_STORAGE_BIT);
}

void AdvectionPass::resize(glm::ivec2 target) {
  if (target == size_) return;
  size_ = target;
  for (int i = 0; i < 2; ++i) {
    state_[i] = Texture::create2D(GL_RG32F, target.x, target.y);
    state_[i].setFilter(GL_LINEAR, GL_LINEAR);
    fbo_[i] = createFramebuffer();
    attachTargets(fbo_[i], {&state_[i]}, nullptr);
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(fbo_[i].id(), GL_COLOR, 0, zero);
  }
  current_ = 0;
}

void AdvectionPass::step(const Texture& vectors, const Texture& surface, const Texture& edges, float k,
                         float stepPx, float epsilon, bool countChanges) {
  const int next = 1 - current_;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_[next].id());
  glViewport(0, 0, size_.x, size_.y);
  program_.set("u_k", k);
  program_.set("u_step", stepPx);
  program_.set("u_epsilon", epsilon);
  program_.set("u_count", countChanges ? 1 : 0);
  if (countChanges) {
    const GLuint zero = 0;
    glClearNamedBufferSubData(counter_.id(), GL_R32UI, 0, sizeof(GLuint), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  program_.use();
  glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.id());
  glBindTextureUnit(0, state_[current_].id());
  glBindTextureUnit(1, vectors.id());
  glBindTextureUnit(2, surface.id());
  glBindTextureUnit(3, edges.id());
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  current_ = next;
}

void AdvectionPass::reset(const Texture& vectors, const Texture& surface, const Texture& edges) {
  resize({surface.width(), surface.height()});
  step(vectors, surface, edges, 1.0f, 0.0f, 0.0f, false);
}

void AdvectionPass::iterate(const Texture& vectors, const Texture& surface, const Texture& edges,
                            const AdvectionSettings& s, int count, bool countChanges) {
  resize({surface.width(), surface.height()});
  for (int i = 0; i < count; ++i)
    step(vectors, surface, edges, s.k, s.stepPixels, s.epsilon, countChanges && i == count - 1);
}

void AdvectionPass::setState(const float* rg) {
  glTextureSubImage2D(state_[current_].id(), 0, 0, 0, size_.x, size_.y, GL_RG, GL_FLOAT, rg);
}

unsigned AdvectionPass::changedPixels() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint v = 0;
  glGetNamedBufferSubData(counter_.id(), 0, sizeof(GLuint), &v);
  return v;
}

} // namespace dtf::render
