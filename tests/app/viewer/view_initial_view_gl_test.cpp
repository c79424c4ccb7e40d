// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer opens in the selected display convention, as `dtfabric render --view axial`: radiological by
// default (the patient's right on the image's left), neurological when chosen, whatever the first surface;
// the pane's edge letters name the side the camera puts there.
#include "app/viewer/viewer.h"
#include "render/camera.h"
#include "support/gl_test.h"
#include "ui/session/orientation_labels.h"

#include <chrono>
#include <thread>

namespace {

using dtf::render::Camera;

void loadPhantom(dtf::app::ViewerScene& scene) {
  scene.apply(dtf::session::LoadFile{
      (dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string(), "auto"});
  for (int i = 0; i < 3000 && !scene.settled(); ++i) {
    scene.update();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  scene.update();
  scene.render(200, 160);
}

// Screen x in [-1, 1] of a world point through the pane's camera.
double screenX(const Camera& c, const glm::dvec3& world) {
  const glm::dvec4 clip = c.projection(1.25) * c.view() * glm::dvec4(world, 1.0);
  return clip.x / clip.w;
}

} // namespace

TEST(ViewInitialView, RadiologicalByDefaultForEveryFirstSurface) {
  DTF_GL_TEST_SETUP();
  for (const char* surface : {"", "slice=axial", "fa=0.3"}) {
    SCOPED_TRACE(std::string("first surface '") + surface + "'");
    dtf::app::ViewerScene scene(surface);
    loadPhantom(scene);
    ASSERT_TRUE(scene.state().errorChain.empty()) << scene.state().errorChain.back();
    ASSERT_TRUE(scene.state().hasData);
    EXPECT_FALSE(scene.state().neurological);
    const Camera& c = scene.camera(0);
    // Looking from the feet with anterior up: the patient's right (+x) on the image's left.
    const glm::dvec3 centre = c.target;
    EXPECT_LT(screenX(c, centre + glm::dvec3(40, 0, 0)), screenX(c, centre - glm::dvec3(40, 0, 0)))
        << "the patient's right is not on the image's left";
    EXPECT_GT(c.up.y, 0.99) << "anterior is not up";
    EXPECT_STREQ(dtf::session::anatomicalLabel(-c.right()), "R") << "left edge";
    EXPECT_STREQ(dtf::session::anatomicalLabel(c.right()), "L") << "right edge";
    EXPECT_STREQ(dtf::session::anatomicalLabel(c.up), "A") << "top edge";
    // The same orientation as `dtfabric render --view axial`.
    const Camera batch =
        Camera::standard(dtf::render::StandardView::Axial, glm::dvec3(-1), glm::dvec3(1), 1.0);
    EXPECT_GT(glm::dot(c.forward(), batch.forward()), 0.999);
    EXPECT_GT(glm::dot(c.right(), batch.right()), 0.999);
  }
}

TEST(ViewInitialView, NeurologicalWhenChosen) {
  DTF_GL_TEST_SETUP();
  dtf::app::ViewerScene scene;
  loadPhantom(scene);
  scene.apply(dtf::session::SetNeurological{true});
  scene.apply(dtf::session::ResetView{});
  const Camera& c = scene.camera(0);
  const glm::dvec3 centre = c.target;
  EXPECT_GT(screenX(c, centre + glm::dvec3(40, 0, 0)), screenX(c, centre - glm::dvec3(40, 0, 0)))
      << "neurological: the patient's right on the image's right";
  EXPECT_STREQ(dtf::session::anatomicalLabel(c.right()), "R");
}
