// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer scene (app/viewer/viewer.h) headless with the window's frame loop minus ImGui: frames until the
// session is settled and every pane is still, and the panes as the window would show them. Needs the GL test
// context (support/gl_test.h).
#pragma once

#include "app/viewer/viewer.h"
#include "io/model/image.h"
#include "render/gl_objects.h"

#include <chrono>
#include <cstring>
#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <string>
#include <thread>
#include <vector>

namespace dtf::test {

// The viewer scene with the frame loop of the window, minus ImGui.
struct ViewScene {
  using Clock = std::chrono::steady_clock;
  app::ViewerScene scene;
  explicit ViewScene(const std::string& surface) : scene(surface) {}

  void frame(int w = 256, int h = 256) {
    scene.update();
    scene.render(w, h);
  }
  // Frames until the workers are idle and every pane (tracts included) is still.
  void converge(double timeout = 180) {
    const auto t0 = Clock::now();
    do {
      frame();
      if (!scene.settled()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ASSERT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), timeout)
          << "the scene did not settle";
    } while (!scene.settled() || !scene.converged());
    frame();
    ASSERT_TRUE(scene.converged());
  }
  void apply(const session::Action& a) { scene.apply(a); }
  const session::ViewerState& state() const { return scene.state(); }
  std::string lastError() const { return state().errorChain.empty() ? "" : state().errorChain.back(); }
  // What the window would show: the panes blitted into a w x h target, row 0 at the top.
  Image image(int w = 256, int h = 256) {
    render::Texture colour = render::Texture::create2D(GL_RGBA8, w, h);
    render::Framebuffer fbo = render::createFramebuffer();
    render::attachTargets(fbo, {&colour}, nullptr);
    const float black[4] = {0, 0, 0, 1};
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, black);
    scene.present(fbo.id(), 0, 0);
    Image img(w, h);
    std::vector<std::uint8_t> rows(img.rgba.size());
    glGetTextureImage(colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rows.size()),
                      rows.data());
    const std::size_t stride = static_cast<std::size_t>(w) * 4;
    for (int y = 0; y < h; ++y)
      std::memcpy(&img.rgba[static_cast<std::size_t>(y) * stride],
                  &rows[static_cast<std::size_t>(h - 1 - y) * stride], stride);
    return img;
  }
};

} // namespace dtf::test
