// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation banner (ui/orientation_banner.h) headless: what it offers for each verdict and the action
// each button returns.
#include "ui/panels/orientation_banner.h"

#include <gtest/gtest.h>
#include <imgui.h>

namespace {

using namespace dtf::ui;

class OrientationBannerUi : public ::testing::Test {
protected:
  void SetUp() override {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(1280, 800);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
  }
  void TearDown() override { ImGui::DestroyContext(); }

  OrientationAction frame(float x, float y, bool down) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(x, y);
    io.MouseDown[0] = down;
    ImGui::NewFrame();
    const float rect[4] = {300, 0, 980, 774};
    const OrientationAction a = orientationBanner(state, rect, &centres);
    ImGui::Render();
    return a;
  }
  OrientationAction click(const std::string& label) {
    centres.clear();
    frame(-1, -1, false);
    EXPECT_TRUE(centres.count(label)) << "no button '" << label << "'";
    if (!centres.count(label)) return OrientationAction::None;
    const auto c = centres[label];
    OrientationAction last = OrientationAction::None;
    for (bool down : {false, true, false}) {
      const OrientationAction a = frame(c[0], c[1], down);
      if (a != OrientationAction::None) last = a;
    }
    return last;
  }

  OrientationBannerState state;
  std::map<std::string, std::array<float, 2>> centres;
};

TEST_F(OrientationBannerUi, HiddenWithoutAResult) {
  EXPECT_EQ(frame(-1, -1, false), OrientationAction::None);
  EXPECT_TRUE(centres.empty());
}

TEST_F(OrientationBannerUi, CorrectedOffersTheCorrectionAndTheEvidence) {
  state.visible = true;
  state.verdict = "corrected";
  state.correction = "-x y z";
  state.reason = "the table -x y z scores 14.4% above the next";
  EXPECT_EQ(click("Apply correction"), OrientationAction::ApplyCorrection);
  EXPECT_EQ(click("Show evidence"), OrientationAction::ShowSheet);
  EXPECT_EQ(click("Dismiss"), OrientationAction::Dismiss);
  state.applied = true; // applied: no second correction
  centres.clear();
  frame(-1, -1, false);
  EXPECT_FALSE(centres.count("Apply correction"));
  state.sheetShown = true;
  EXPECT_EQ(click("Hide evidence"), OrientationAction::HideSheet);
}

TEST_F(OrientationBannerUi, OkShowsNothingAndInconclusiveOffersNoCorrection) {
  state.visible = true;
  state.verdict = "ok";
  frame(-1, -1, false);
  EXPECT_TRUE(centres.empty());
  state.running = true;
  state.verdict = "";
  frame(-1, -1, false);
  EXPECT_TRUE(centres.empty());
  state.running = false;
  state.verdict = "inconclusive";
  frame(-1, -1, false);
  EXPECT_FALSE(centres.count("Apply correction"));
  EXPECT_TRUE(centres.count("Show evidence"));
  EXPECT_TRUE(centres.count("Dismiss"));
  float ok[3], bad[3];
  orientationBannerColour("ok", ok);
  orientationBannerColour("corrected", bad);
  EXPECT_GT(ok[1], ok[0]);
  EXPECT_GT(bad[0], bad[1]);
}

} // namespace
