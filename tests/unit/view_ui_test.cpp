// The ui panels and key map without a window: pure state -> action functions, and the ImGui panels run
// headless (a context, a font atlas, no renderer backend) with simulated mouse clicks.
#include "ui/keymap.h"
#include "ui/panels.h"

#include <gtest/gtest.h>
#include <imgui.h>
#include <map>
#include <optional>

using namespace dtf;
using namespace dtf::ui;

namespace {

ViewerState sliceState(SurfaceKind kind, int index, int count) {
  ViewerState s;
  s.hasData = true;
  s.surface = kind;
  s.sliceCount = {count, count, count};
  s.slice = {index, index, index};
  return s;
}

// One headless ImGui context with the panels drawn each frame.
class ViewHeadlessUi : public ::testing::Test {
protected:
  void SetUp() override {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(1280, 800);
    io.DeltaTime = 1.0f / 60.0f;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h); // builds the atlas; no renderer needed
    buffers.itemCentres = &centres;
  }
  void TearDown() override { ImGui::DestroyContext(); }

  // Runs one frame with the mouse at (x, y), button 0 down or not; returns the actions.
  ActionList frame(float x, float y, bool down) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(x, y);
    io.MouseDown[0] = down;
    ImGui::NewFrame();
    ActionList out;
    drawPanels(state, buffers, layout, out);
    ImGui::Render();
    return out;
  }
  // Presses and releases the left button on a widget; returns all actions of those frames.
  ActionList click(const std::string& label) {
    frame(-1, -1, false); // lay out, learn where the widget is
    EXPECT_TRUE(centres.count(label)) << "no widget '" << label << "' was drawn";
    const auto c = centres[label];
    ActionList all;
    for (bool down : {false, true, false}) {
      auto a = frame(c[0], c[1], down);
      all.insert(all.end(), a.begin(), a.end());
    }
    return all;
  }

  ViewerState state = sliceState(SurfaceKind::FaIsosurface, 10, 40);
  PanelBuffers buffers;
  PanelLayout layout;
  std::map<std::string, std::array<float, 2>> centres;
};

// The first action of type T (a copy: the lists are temporaries).
template <typename T> std::optional<T> find(const ActionList& list) {
  for (const auto& a : list)
    if (const auto t = std::get_if<T>(&a)) return *t;
  return std::nullopt;
}

} // namespace

TEST(ViewKeymap, UpDownPageStepTheSliceWithinTheGrid) {
  ActionList out;
  keyActions(Key::Up, sliceState(SurfaceKind::Coronal, 10, 40), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<SetSlice>(out[0]).axis, 1);
  EXPECT_EQ(std::get<SetSlice>(out[0]).index, 11);
  out.clear();
  keyActions(Key::PageDown, sliceState(SurfaceKind::Axial, 4, 40), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<SetSlice>(out[0]).index, 0); // clamped, not -6
  out.clear();
  keyActions(Key::Up, sliceState(SurfaceKind::Sagittal, 39, 40), out);
  EXPECT_TRUE(out.empty()) << "already at the last slice";
  keyActions(Key::Up, sliceState(SurfaceKind::FaIsosurface, 5, 40), out);
  EXPECT_TRUE(out.empty()) << "no slice on screen";
  ViewerState none = sliceState(SurfaceKind::Axial, 0, 1);
  none.hasData = false;
  keyActions(Key::Down, none, out);
  EXPECT_TRUE(out.empty());
}

TEST(ViewKeymap, LettersPickSliceAndViewAndReset) {
  ActionList out;
  keyActions(Key::S, sliceState(SurfaceKind::FaIsosurface, 0, 10), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(std::get<SetSurfaceKind>(out[0]).kind, SurfaceKind::Sagittal);
  EXPECT_EQ(std::get<SetView>(out[1]).view, render::StandardView::Sagittal);
  out.clear();
  keyActions(Key::R, sliceState(SurfaceKind::Axial, 0, 10), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<ResetView>(out[0]));
  EXPECT_EQ(parseKey("pgdn"), Key::PageDown);
  EXPECT_EQ(parseKey("c"), Key::C);
  EXPECT_FALSE(parseKey("Escape").has_value());
}

TEST(ViewPanels, ErrorChainSplitsAtContexts) {
  const auto links =
      splitErrorChain("while loading a.nii: while reading tensor volume a.nii: a.nii: truncated");
  ASSERT_EQ(links.size(), 3u);
  EXPECT_EQ(links[0], "while loading a.nii");
  EXPECT_EQ(links[1], "while reading tensor volume a.nii");
  EXPECT_EQ(links[2], "a.nii: truncated");
  EXPECT_EQ(splitErrorChain("plain: message").size(), 1u);
  EXPECT_EQ(splitErrorChain("").size(), 1u);
}

TEST(ViewPanels, SceneRectLeavesRoomForPanels) {
  float r[4];
  sceneRect(PanelLayout{300, 26}, 1280, 800, r);
  EXPECT_FLOAT_EQ(r[0], 300);
  EXPECT_FLOAT_EQ(r[2], 980);
  EXPECT_FLOAT_EQ(r[3], 774);
}

TEST_F(ViewHeadlessUi, NoInputNoActions) {
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(frame(-1, -1, false).empty());
  EXPECT_GT(centres.size(), 10u) << "panels drew their widgets";
}

TEST_F(ViewHeadlessUi, ViewPresetButtonsSetTheView) {
  const auto actions = click("anterior");
  const auto v = find<SetView>(actions);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->view, render::StandardView::Anterior);
  EXPECT_EQ(actions.size(), 1u);
}

TEST_F(ViewHeadlessUi, SplitCheckboxTogglesSplit) {
  const auto s = find<SetSplit>(click("split"));
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->on);
  state.split = true;
  const auto off = find<SetSplit>(click("split"));
  ASSERT_TRUE(off);
  EXPECT_FALSE(off->on);
}

TEST_F(ViewHeadlessUi, FaSliderSendsTheThresholdUnderTheMouse) {
  const auto actions = click("FA threshold");
  const auto t = find<SetFaThreshold>(actions);
  ASSERT_TRUE(t);
  // A click at the slider's centre sets the middle of its range [0.05, 0.9].
  EXPECT_NEAR(t->value, 0.475, 0.06);
}

TEST_F(ViewHeadlessUi, SliceSlidersAreDisabledUnlessTheirSliceIsShown) {
  EXPECT_FALSE(find<SetSlice>(click("coronal slice"))) << "FA isosurface on screen: slice sliders disabled";
  state.surface = SurfaceKind::Coronal;
  const auto s = find<SetSlice>(click("coronal slice"));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->axis, 1);
  EXPECT_NEAR(s->index, 20, 1);
}

TEST_F(ViewHeadlessUi, OpenButtonLoadsTheTypedPath) {
  std::snprintf(buffers.openPath.data(), buffers.openPath.size(), "/data/dti.nii.gz");
  buffers.layout = 2;
  const auto l = find<LoadFile>(click("Open"));
  ASSERT_TRUE(l);
  EXPECT_EQ(l->path, "/data/dti.nii.gz");
  EXPECT_EQ(l->layout, "mrtrix");
}

TEST_F(ViewHeadlessUi, ErrorModalOpensAndOkDismisses) {
  state.errorChain = {"while loading x.nii", "x.nii: file does not exist"};
  frame(-1, -1, false);
  frame(-1, -1, false);
  // The modal blocks the panels: clicking a preset under it does nothing.
  EXPECT_FALSE(find<SetView>(click("anterior")));
  const auto d = find<DismissError>(click("OK"));
  EXPECT_TRUE(d);
}

TEST_F(ViewHeadlessUi, OverwritePromptAsksBeforeReplacingAFile) {
  frame(-1, -1, false);
  EXPECT_FALSE(centres.count("Overwrite")) << "no prompt without a pending output";
  state.overwritePath = "/figures/fig1.png";
  frame(-1, -1, false);
  frame(-1, -1, false);
  // Modal: the panels under it take no clicks.
  EXPECT_FALSE(find<SetView>(click("anterior")));
  const auto cancel = find<ConfirmOverwrite>(click("Cancel"));
  ASSERT_TRUE(cancel);
  EXPECT_FALSE(cancel->overwrite);
  // The viewer clears the question on the answer; a later one opens the prompt again.
  state.overwritePath.clear();
  frame(-1, -1, false);
  state.overwritePath = "/figures/fig2.png";
  frame(-1, -1, false);
  frame(-1, -1, false);
  const auto yes = find<ConfirmOverwrite>(click("Overwrite"));
  ASSERT_TRUE(yes);
  EXPECT_TRUE(yes->overwrite);
}

TEST_F(ViewHeadlessUi, AnErrorHidesTheOverwritePromptUntilDismissed) {
  state.overwritePath = "/figures/fig1.png";
  state.errorChain = {"while saving: disk full"};
  frame(-1, -1, false);
  frame(-1, -1, false);
  EXPECT_FALSE(centres.count("Overwrite"));
  EXPECT_TRUE(centres.count("OK"));
}

TEST_F(ViewHeadlessUi, FibreSeedFromTheViewerFillsTheSeedFieldsAndBuildSendsIt) {
  state.surface = SurfaceKind::Fibre;
  state.fibreSeed = {17, 12, 24, 23, 12, 24};
  state.fibreSeedSerial = 1;
  frame(-1, -1, false);
  EXPECT_EQ(buffers.fibreFrom, (std::array<int, 3>{17, 12, 24}));
  EXPECT_EQ(buffers.fibreTo, (std::array<int, 3>{23, 12, 24}));
  const auto spec = find<SetSurfaceSpec>(click("Build fibre surface"));
  ASSERT_TRUE(spec);
  EXPECT_EQ(spec->text, "fibre-voxel=17,12,24:23,12,24");
}
