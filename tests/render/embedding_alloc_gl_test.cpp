// SPDX-License-Identifier: GPL-3.0-or-later
// EmbeddedFabric::draw does not allocate in a host's frame loop: frames with a fixed camera (the advection
// continues) and frames with a turning camera (it restarts), after a warm-up. Counts every operator new of
// this process during the frames (headless GL).
#include "render/embedding.h"
#include "render/reference/scenes.h"
#include "support/counting_allocator.h"
#include "support/gl_test.h"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <new>
#include <vector>

using dtf::test::allocations;
using dtf::test::counting;

TEST(EmbeddingAlloc, HostFramesDoNotAllocate) {
  DTF_GL_TEST_SETUP();
  // A host's depth and normal textures: a plane facing the camera (depth 0.5, normal +z), drawn by clearing.
  constexpr int w = 96, h = 80;
  GLuint tex[2] = {0, 0}, fbo = 0;
  glCreateTextures(GL_TEXTURE_2D, 2, tex);
  glTextureStorage2D(tex[0], 1, GL_DEPTH_COMPONENT32F, w, h);
  glTextureStorage2D(tex[1], 1, GL_RGBA16F, w, h);
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex[1], 0);
  glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, tex[0], 0);
  const float normal[4] = {0, 0, 1, 1}, depth = 0.5f;
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, normal);
  glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &depth);
  GLuint target[2] = {0, 0}, targetFbo = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, target);
  glTextureStorage2D(target[0], 1, GL_RGBA8, w, h);
  glCreateFramebuffers(1, &targetFbo);
  glNamedFramebufferTexture(targetFbo, GL_COLOR_ATTACHMENT0, target[0], 0);
  {
    dtf::render::EmbeddedFabric fabric;
    fabric.setField(
        dtf::render::reference::constantField(dtf::render::reference::centredGrid(24, 4.0), {1, 1, 0}));
    dtf::render::HostView v;
    v.depthTexture = tex[0];
    v.normalTexture = tex[1];
    v.projection = glm::ortho(-48.0f, 48.0f, -40.0f, 40.0f, 1.0f, 200.0f);
    v.viewport = {0, 0, w, h};
    v.framebuffer = targetFbo;
    dtf::render::FabricParams p;
    auto viewAt = [](float angle) {
      return glm::lookAt(glm::vec3(100.0f * std::sin(angle), 0.0f, 100.0f * std::cos(angle)), glm::vec3(0.0f),
                         glm::vec3(0, 1, 0));
    };
    for (int i = 0; i < 6; ++i) { // warm-up of turning and fixed frames: programs, noise, targets
      v.view = viewAt(0.01f * float(i < 3 ? i : 3));
      fabric.draw(v, p);
    }
    allocations = 0;
    counting = true;
    for (int i = 0; i < 5; ++i)
      fabric.draw(v, p); // fixed camera
    const long still = allocations.exchange(0);
    for (int i = 0; i < 5; ++i) { // turning camera
      v.view = viewAt(0.05f + 0.01f * float(i));
      fabric.draw(v, p);
    }
    const long moving = allocations.load();
    auto probe = std::make_unique<std::vector<int>>(100); // the counter sees allocations at all
    counting = false;
    glFinish();
    EXPECT_GE(allocations.load() - moving, 2);
    EXPECT_EQ(still, 0);
    EXPECT_EQ(moving, 0);
  }
  glDeleteFramebuffers(1, &fbo);
  glDeleteFramebuffers(1, &targetFbo);
  glDeleteTextures(2, tex);
  glDeleteTextures(1, target);
}
