// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer scene's steady state does not allocate: frames of a still, converged scene, and interactive
// frames while the camera rotates, run without a heap allocation in the viewer's own code. Counts every
// operator new of this process between frames (headless GL; skips without a context).
#include "app/viewer/viewer.h"
#include "io/formats/tracts.h"
#include "support/counting_allocator.h"
#include "support/gl_test.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <new>
#include <thread>
#include <utility>
#include <vector>

using dtf::test::allocations;
using dtf::test::counting;

// Allocations during 5 still frames and during 5 frames of a turning camera, after a warm-up of both kinds
// of frame (the renderer's targets are created, and the driver compiles each program for its state, on first
// use). Leaves the counter off.
std::pair<long, long> countStillAndMoving(dtf::app::ViewerScene& scene) {
  for (int round = 0; round < 2; ++round) {
    for (int i = 0; i < 3; ++i) {
      scene.apply(dtf::session::Rotate{4, 0});
      scene.update();
      scene.render(160, 120);
    }
    for (int i = 0; i < 3 && round == 0; ++i) { // still frames refining after the turn
      scene.update();
      scene.render(160, 120);
    }
  }
  allocations = 0;
  counting = true;
  for (int i = 0; i < 5; ++i) {
    scene.update();
    scene.render(160, 120); // still: nothing to do
  }
  const long still = allocations.exchange(0);
  for (int i = 0; i < 5; ++i) {
    scene.apply(dtf::session::Rotate{4, 0});
    scene.update();
    scene.render(160, 120);
  }
  counting = false;
  return {still, allocations.load()};
}

TEST(ViewScene, FramesDoNotAllocate) {
  DTF_GL_TEST_SETUP();
  dtf::app::ViewerScene scene("slice=axial");
  scene.apply(dtf::session::LoadFile{
      (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string(), "auto"});
  for (int i = 0; i < 3000 && !scene.settled(); ++i) {
    scene.update();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  scene.update();
  ASSERT_TRUE(scene.state().errorChain.empty()) << scene.state().errorChain.back();
  ASSERT_TRUE(scene.state().hasData);
  // 2 ms a frame: the frames of the viewer's motion window (wall time) are interactive, however many fit.
  for (int i = 0; i < 400 && !scene.converged(); ++i) {
    scene.update();
    scene.render(160, 120);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(scene.converged());
  const auto [still, moving] = countStillAndMoving(scene);
  // The counter sees allocations at all (the replaced operator new is the one in use).
  counting = true;
  auto probe = std::make_unique<std::vector<int>>(100);
  counting = false;
  EXPECT_GE(allocations.load() - moving, 2);
  EXPECT_EQ(still, 0);
  EXPECT_EQ(moving, 0) << "interactive frames allocated " << moving << " times";
}

TEST(ViewScene, FramesWithTractsDoNotAllocate) {
  DTF_GL_TEST_SETUP();
  // 400 helices of 150 points through the phantom's slab around the middle axial slice.
  dtf::Polylines lines;
  lines.offsets = {0};
  for (int i = 0; i < 400; ++i) {
    for (int k = 0; k < 150; ++k) {
      const float t = float(k) / 149.0f;
      lines.points.emplace_back(float(i % 20) * 6.0f - 60.0f + 3.0f * std::cos(9.0f * t),
                                float(i / 20) * 6.0f - 60.0f + 3.0f * std::sin(9.0f * t), 20.0f * t - 8.0f);
    }
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  const auto tck = dtf::test::scratchDir() / "helices.tck";
  dtf::io::writeTck(tck.string(), lines);
  dtf::app::ViewerScene scene("slice=axial");
  scene.apply(dtf::session::LoadFile{
      (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string(), "auto"});
  scene.apply(dtf::session::LoadTracts{tck.string()});
  // The fabric along the tracts and the Profile panel on: their workers are polled every frame.
  scene.apply(dtf::session::SetFabricAlong{true, 2.0});
  scene.apply(dtf::session::SetProfile{true, {}});
  for (int i = 0; i < 3000 && !(scene.settled() && scene.converged()); ++i) {
    scene.update();
    scene.render(160, 120);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(scene.state().errorChain.empty()) << scene.state().errorChain.back();
  ASSERT_TRUE(scene.converged());
  ASSERT_TRUE(scene.paneShowsTracts(0));
  ASSERT_GT(scene.state().tractsShownPoints, 0u);
  ASSERT_TRUE(scene.paneRenderer(0).hasAlong());
  ASSERT_EQ(scene.state().profile.core.size(), 100u) << scene.state().profile.error;
  const auto [still, moving] = countStillAndMoving(scene);
  allocations = 0;
  // The camera stops: still refinement of the fabric and the full tract set, until converged.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  counting = true;
  int refining = 0;
  for (; refining < 400 && !scene.converged(); ++refining) {
    scene.update();
    scene.render(160, 120);
  }
  counting = false;
  EXPECT_GT(refining, 0);
  EXPECT_TRUE(scene.converged());
  EXPECT_EQ(still, 0);
  EXPECT_EQ(moving, 0) << "interactive frames with tracts allocated " << moving << " times";
  EXPECT_EQ(allocations.load(), 0) << "refining frames with tracts allocated " << allocations.load()
                                   << " times";
}
