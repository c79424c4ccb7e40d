// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's still refinement follows the rule of `dtfabric render` (FabricRenderer::renderStill): once
// the camera stops, the fabric refines until almost no covered pixel changes by more than epsilon, but not
// before the start image's weight (1 - k)^n has fallen below epsilon (paper §2.5), so the settled pane is as
// converged as a rendered still.
#include "render/fabric_params.h"
#include "support/gl_test.h"
#include "support/view_scene.h"

#include <chrono>

namespace {

const std::string kPhantom = (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string();

} // namespace

TEST(ViewRefine, StillRefinementRunsAtLeastTheIterationsOfARenderedStill) {
  DTF_GL_TEST_SETUP();
  for (const char* surface : {"slice=axial", "fa=0.25"}) {
    SCOPED_TRACE(surface);
    dtf::test::ViewScene v(surface);
    v.apply(dtf::session::LoadFile{kPhantom, "auto"});
    v.converge();
    ASSERT_TRUE(v.state().errorChain.empty()) << v.lastError();
    const dtf::render::FabricParams& p = v.state().fabric;
    const int least = p.stillMinIterations();
    EXPECT_GE(least, 29) << "k 0.1, epsilon 0.05: 0.9^n < 0.05 from n = 29";
    // A turn of the camera, then still frames until the pane is converged.
    for (int turn = 0; turn < 3; ++turn) {
      v.apply(dtf::session::Rotate{6, 0});
      v.frame();
      EXPECT_FALSE(v.scene.converged());
      // The frames within the viewer's motion window (wall time) after the turn are interactive, however many
      // fit in it; then the still frames refine. Bounded by time, not by a count of frames.
      const auto t0 = std::chrono::steady_clock::now();
      int frames = 0;
      for (; !v.scene.converged() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60); ++frames)
        v.frame();
      ASSERT_TRUE(v.scene.converged()) << "still refining after " << frames << " frames";
      EXPECT_GE(v.scene.refinedIterations(0), least) << "turn " << turn;
      EXPECT_LE(v.scene.refinedIterations(0), std::max(p.stillMaxIterations, least) + 16) << "turn " << turn;
    }
  }
}
