// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's orientation check (app/viewer_orientation.h) on a headless scene: a DWI whose table has its x
// row negated is loaded, the banner reports the correction, "Apply correction" turns the scene's tensors
// into those of the true table, and "Show evidence" renders the contact sheet into a texture. ImGui runs
// headless (font atlas, no backend) with simulated clicks.
#include "app/viewer/viewer.h"
#include "app/viewer/viewer_orientation.h"
#include "io/diffusion/dwi.h"
#include "support/gl_test.h"

#include <chrono>
#include <fstream>
#include <imgui.h>
#include <thread>

namespace {

using namespace dtf;

struct HeadlessImGui {
  HeadlessImGui() {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(1280, 800);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
  }
  ~HeadlessImGui() { ImGui::DestroyContext(); }
};

class ViewerOrientationCheck : public GlTest {
protected:
  void frame(float x, float y, bool down) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(x, y);
    io.MouseDown[0] = down;
    ImGui::NewFrame();
    const float rect[4] = {300, 0, 980, 774};
    check.frame(*scene, rect, &centres);
    ImGui::Render();
  }
  void click(const std::string& label) {
    centres.clear();
    frame(-1, -1, false);
    ASSERT_TRUE(centres.count(label)) << "no button '" << label << "'";
    const auto c = centres[label];
    for (bool down : {false, true, false})
      frame(c[0], c[1], down);
  }
  void SetUp() override {
    GlTest::SetUp();
    if (!IsSkipped()) scene = std::make_unique<app::ViewerScene>("slice=axial:22");
  }
  void TearDown() override {
    check.release();
    scene.reset();
    GlTest::TearDown();
  }

  HeadlessImGui imgui;
  std::unique_ptr<app::ViewerScene> scene; // made once the GL context is current
  app::ViewerOrientation check;
  std::map<std::string, std::array<float, 2>> centres;
};

TEST_F(ViewerOrientationCheck, FlippedTableIsCorrectedInMemory) {
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  const auto dir = dwi.parent_path();
  const auto scratch = test::scratchDir();
  std::filesystem::copy_file(dwi, scratch / "dwi.nii.gz");
  std::filesystem::copy_file(dir / "dwi.bval", scratch / "dwi.bval");
  const auto bvecs = io::readBvecs((dir / "dwi.bvec").string());
  {
    std::ofstream os(scratch / "dwi.bvec");
    for (int r = 0; r < 3; ++r) {
      for (std::size_t n = 0; n < bvecs.size(); ++n)
        os << (n ? " " : "") << (r == 0 ? -bvecs[n][r] : bvecs[n][r]);
      os << "\n";
    }
  }
  scene->apply(session::LoadFile{(scratch / "dwi.nii.gz").string(), "auto"});
  for (int i = 0; i < 3000 && !scene->settled(); ++i) {
    scene->update();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  scene->update();
  ASSERT_TRUE(scene->state().hasData);
  for (int i = 0; i < 2000 && (i == 0 || check.banner().running); ++i) {
    frame(-1, -1, false);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(check.banner().visible);
  ASSERT_EQ(check.banner().verdict, "corrected") << check.banner().reason;
  EXPECT_EQ(check.banner().correction, "-x y z");

  const TensorField before = scene->dataset()->loaded.field;
  click("Apply correction");
  EXPECT_TRUE(check.banner().applied);
  const TensorField& after = scene->dataset()->loaded.field;
  // The true table's fit, with the same automatic mask (it depends on the signals only).
  io::Dwi truth = io::readDwi(dwi.string(), (dir / "dwi.bval").string(), (dir / "dwi.bvec").string());
  const TensorField expected = io::fitTensors(truth, nullptr, io::FitOptions{});
  std::size_t n = 0, off = 0, changed = 0;
  for (std::size_t i = 0; i < after.tensors.size(); ++i) {
    if (!expected.valid[i]) continue;
    const auto a = after.tensors[i].components(), e = expected.tensors[i].components(),
               b = before.tensors[i].components();
    double diff = 0, norm = 0, moved = 0;
    for (int c = 0; c < 6; ++c) {
      diff = std::max(diff, double(std::abs(a[c] - e[c])));
      moved = std::max(moved, double(std::abs(a[c] - b[c])));
      norm = std::max(norm, double(std::abs(e[c])));
    }
    off += diff > 1e-3 * norm;
    changed += moved > 1e-3 * norm;
    ++n;
  }
  EXPECT_GT(n, 40000u);
  EXPECT_LE(off, 2u);
  EXPECT_GT(changed, n / 2);
  // The corrected data is not checked again, and the banner offers no second correction.
  centres.clear();
  for (int i = 0; i < 5; ++i)
    frame(-1, -1, false);
  EXPECT_FALSE(check.banner().running);
  EXPECT_FALSE(centres.count("Apply correction"));

  click("Show evidence");
  EXPECT_TRUE(check.banner().sheetShown);
  EXPECT_NE(check.banner().sheetTexture, 0u);
  EXPECT_EQ(check.banner().sheetWidth, 3 * 192);
}

} // namespace
