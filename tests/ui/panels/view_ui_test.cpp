// SPDX-License-Identifier: GPL-3.0-or-later
// The ui panels and key map without a window: pure state -> action functions, and the ImGui panels run
// headless (a context, a font atlas, no renderer backend) with simulated mouse clicks.
#include "ui/panels/panels.h"
#include "ui/session/keymap.h"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>
#include <map>
#include <optional>
#include <unistd.h>

using namespace dtf;
using namespace dtf::ui;
using namespace dtf::session;

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
    io.DisplaySize = ImVec2(1280, 1600); // tall enough that every panel widget is laid out unclipped
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

namespace {
// The Tracts panel lies at the bottom of the side bar: a tall display keeps it on screen.
class ViewTractsPanel : public ViewHeadlessUi {
protected:
  void SetUp() override {
    ViewHeadlessUi::SetUp();
    ImGui::GetIO().DisplaySize = ImVec2(1280, 3000);
    state.tractPath = "/data/tracks.tck";
    state.tractCount = 2000;
    state.tractPoints = 147545;
  }
  // Opens the Tracts header, and the tree nodes named.
  void open(std::initializer_list<const char*> nodes = {}) {
    click("Tracts");
    for (const char* n : nodes)
      click(n);
  }
};
} // namespace

TEST_F(ViewTractsPanel, ShowCheckboxAndDistanceSliderSendTheirActions) {
  open();
  const auto v = find<SetTractsVisible>(click("show tracts"));
  ASSERT_TRUE(v);
  EXPECT_FALSE(v->on);
  const auto n = find<SetTractsNear>(click("near surface (mm)"));
  ASSERT_TRUE(n);
  EXPECT_NEAR(n->mm, 10.0, 1.0); // the middle of 0..20 mm
  const auto w = find<SetTractWidth>(click("width (px)"));
  ASSERT_TRUE(w);
  EXPECT_NEAR(w->px, 4.25, 0.4); // the middle of 0.5..8 px
}

TEST_F(ViewTractsPanel, ClipSlabSliderSendsHalfWidthThenDepth) {
  open();
  EXPECT_FALSE(centres.count("clip depth (mm)")) << "no depth slider while the clip is off";
  const auto c = find<SetTractsClip>(click("clip slab (mm)"));
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->mm, 25.0, 2.5); // the middle of 0..50 mm
  EXPECT_DOUBLE_EQ(c->offsetMm, 0.0);
  state.tractsClipMm = 5;
  state.tractsClipOffsetMm = 30;
  frame(-1, -1, false);
  const auto d = find<SetTractsClip>(click("clip depth (mm)"));
  ASSERT_TRUE(d);
  EXPECT_DOUBLE_EQ(d->mm, 5.0) << "the depth slider keeps the half-width";
  EXPECT_NEAR(d->offsetMm, 0.0, 10.0); // the middle of -100..100 mm
}

TEST_F(ViewTractsPanel, TrackSendsTheEditedRequestAndCancelStopsIt) {
  state.hasData = true;
  buffers.track.number = 123;
  buffers.track.seeds = SeedKind::FaMask;
  buffers.track.faMask = 0.45;
  open({"Tracking"});
  const auto t = find<TrackTracts>(click("Track"));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->request.number, 123);
  EXPECT_EQ(t->request.seeds, SeedKind::FaMask);
  EXPECT_DOUBLE_EQ(t->request.faMask, 0.45);
  state.tracking = true;
  state.trackProgress = 0.4;
  EXPECT_TRUE(find<CancelTracking>(click("Cancel")));
  EXPECT_FALSE(centres.count("Track") && find<TrackTracts>(click("Track"))) << "one tracking at a time";
}

TEST_F(ViewTractsPanel, SaveAsksBeforeReplacingAFile) {
  std::snprintf(buffers.tractSavePath.data(), buffers.tractSavePath.size(), "out/t.tck");
  open();
  const auto s = find<SaveTracts>(click("Save"));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->path, "out/t.tck");
  EXPECT_FALSE(s->force) << "the viewer asks before replacing an existing file";
  // The viewer found the file: the overwrite prompt answers with ConfirmOverwrite.
  state.overwritePath = "out/t.tck";
  frame(-1, -1, false);
  frame(-1, -1, false);
  const auto o = find<ConfirmOverwrite>(click("Overwrite"));
  ASSERT_TRUE(o);
  EXPECT_TRUE(o->overwrite);
}

TEST_F(ViewTractsPanel, AgreementComputesWithCompareDefaultsAndShowsTheHistogram) {
  state.hasData = true;
  open({"Agreement with the fabric"});
  const auto a = find<ComputeAgreement>(click("Compute"));
  ASSERT_TRUE(a);
  EXPECT_DOUBLE_EQ(a->nearMm, 2.0);
  EXPECT_EQ(a->bins, 9);
  state.hasAgreement = true;
  state.agreementHistogram = {50, 20, 10, 5, 3, 2, 1, 1, 0};
  state.agreementPoints = 92;
  EXPECT_TRUE(frame(-1, -1, false).empty());
  ASSERT_TRUE(centres.count("agreement histogram"));
  EXPECT_GT(centres["agreement histogram"][0], 70.0f) << "the histogram has the panel's width";
  state.agreementRunning = true;
  EXPECT_FALSE(find<ComputeAgreement>(click("Compute"))) << "disabled while computing";
}

TEST_F(ViewHeadlessUi, FibresSectionAppearsForAFibreSetAndItsSliderSetsTheFibreThreshold) {
  ImGui::GetIO().DisplaySize = ImVec2(1280, 3000); // every section fits
  frame(-1, -1, false);
  EXPECT_FALSE(centres.count("fibre threshold")) << "tensors: no Fibres section";
  state.fibres.present = true;
  state.fibres.path = "/data/peaks.nii.gz";
  state.fibres.layout = "mrtrix-peaks";
  state.fibres.slots = 3;
  state.fibres.voxels = 1000;
  state.fibres.populations = {600, 300, 100};
  state.fabric.colour = render::ColourMode::Fibres;
  const auto p = find<SetFabricParams>(click("fibre threshold"));
  ASSERT_TRUE(p);
  // The option table's range for fibre-threshold is [0, 1]: a click at the slider's centre sets about 0.5;
  // nothing else changes.
  EXPECT_NEAR(p->params.fibreThreshold, 0.5, 0.06);
  EXPECT_EQ(p->params.k, state.fabric.k);
  EXPECT_EQ(p->params.colour, render::ColourMode::Fibres);
  EXPECT_EQ(p->params.iterations, state.fabric.iterations);
}

TEST_F(ViewHeadlessUi, OpenSendsThePairedTensorAndAFibreLayout) {
  std::snprintf(buffers.openPath.data(), buffers.openPath.size(), "/data/peaks.nii.gz");
  std::snprintf(buffers.tensorPath.data(), buffers.tensorPath.size(), "/data/dti.nii.gz");
  buffers.layout = 5;
  const auto l = find<LoadFile>(click("Open"));
  ASSERT_TRUE(l);
  EXPECT_EQ(l->path, "/data/peaks.nii.gz");
  EXPECT_EQ(l->layout, "mrtrix-peaks");
  EXPECT_EQ(l->tensor, "/data/dti.nii.gz");
}

// The in-window browser: a folder listed (its subfolder and the volume, not the text file), a click on the
// volume opens it as the Data panel's Open button opens a typed path (the same LoadFile), the folder is
// remembered, and a click on the subfolder enters it.
TEST_F(ViewHeadlessUi, FileBrowserListsAFolderAndOpensAFileAsTheOpenButtonDoes) {
  const auto dir = std::filesystem::temp_directory_path() / ("dtf_browser_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "sub");
  std::ofstream(dir / "dti.nii.gz") << "x";
  std::ofstream(dir / "notes.txt") << "x";
  std::ofstream(dir / "sub" / "inner.mif") << "x";
  buffers.layout = 2;
  std::snprintf(buffers.tensorPath.data(), buffers.tensorPath.size(), "/data/pair.nii.gz");

  const auto browse = find<Browse>(click("browse data"));
  ASSERT_TRUE(browse) << "the Data panel's ... button asks for a dialog";
  EXPECT_EQ(browse->target, FileTarget::Data);
  openFileBrowser(buffers.browser, browse->target, dir.string()); // the window's fallback
  frame(-1, -1, false);
  frame(-1, -1, false);
  EXPECT_TRUE(centres.count("browser dti.nii.gz"));
  EXPECT_TRUE(centres.count("browser sub"));
  EXPECT_FALSE(centres.count("browser notes.txt")) << "the browser lists only what the target reads";

  const auto chosen = find<LoadFile>(click("browser dti.nii.gz"));
  ASSERT_TRUE(chosen);
  EXPECT_FALSE(buffers.browser.open);
  EXPECT_EQ(buffers.browser.lastFolder, dir.string());
  EXPECT_EQ(std::string(buffers.openPath.data()), (dir / "dti.nii.gz").string());
  // The Open button with that path in the field asks for exactly the same.
  const auto typed = find<LoadFile>(click("Open"));
  ASSERT_TRUE(typed);
  EXPECT_EQ(chosen->path, typed->path);
  EXPECT_EQ(chosen->layout, "mrtrix");
  EXPECT_EQ(chosen->layout, typed->layout);
  EXPECT_EQ(chosen->tensor, typed->tensor);

  openFileBrowser(buffers.browser, FileTarget::Data, {}); // the last folder
  EXPECT_EQ(buffers.browser.listing.folder, dir.string());
  frame(-1, -1, false);
  EXPECT_FALSE(find<LoadFile>(click("browser sub")));
  EXPECT_EQ(buffers.browser.listing.folder, (dir / "sub").string());
  ASSERT_EQ(buffers.browser.listing.entries.size(), 1u);
  EXPECT_EQ(buffers.browser.listing.entries[0].name, "inner.mif");
  std::filesystem::remove_all(dir);
}

TEST_F(ViewHeadlessUi, BrowserChoiceOfAnOutputFillsItsFieldAndSaveSessionSaves) {
  ActionList out;
  choosePath(buffers, FileTarget::Screenshot, "/figures/a.png", out);
  EXPECT_TRUE(out.empty()) << "a screenshot path waits for its button";
  EXPECT_EQ(std::string(buffers.screenshotPath.data()), "/figures/a.png");
  choosePath(buffers, FileTarget::SessionSave, "/figures/view.dtfview", out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<SaveSession>(out[0]).path, "/figures/view.dtfview");
  out.clear();
  choosePath(buffers, FileTarget::Tracts, "/data/t.tck", out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<LoadTracts>(out[0]).path, "/data/t.tck");
}

TEST_F(ViewHeadlessUi, HelpOverlayListsTheBindingsAndF1TogglesIt) {
  ActionList out;
  keyActions(Key::Help, state, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(std::get<ShowHelp>(out[0]).on.has_value()) << "F1 toggles";
  EXPECT_EQ(parseKey("?"), Key::Help);
  EXPECT_EQ(parseKey("F1"), Key::Help);
  state.helpShown = true;
  frame(-1, -1, false);
  frame(-1, -1, false);
  ImGuiWindow* w = ImGui::FindWindowByName("Mouse and keys (F1 or ? to close)");
  ASSERT_NE(w, nullptr) << "the overlay is drawn";
  EXPECT_GE(w->Size.y, static_cast<float>(bindings().size()) * ImGui::GetTextLineHeight())
      << "one row per binding";
  EXPECT_GE(w->Pos.x, layout.sideWidth) << "over the scene, not the side bar";
}

TEST_F(ViewHeadlessUi, PanelOpenStatesAreKeptAndRestored) {
  frame(-1, -1, false);
  EXPECT_TRUE(buffers.panelsOpen.at("Data"));
  EXPECT_FALSE(buffers.panelsOpen.at("Tracts"));
  ImGui::DestroyContext(); // a new run: ImGui remembers nothing, the buffers hold the remembered states
  SetUp();
  buffers.panelsOpen = {{"Data", false}, {"Tracts", true}};
  buffers.panelsRestored = false;
  centres.clear();
  frame(-1, -1, false);
  frame(-1, -1, false);
  EXPECT_FALSE(buffers.panelsOpen.at("Data"));
  EXPECT_TRUE(buffers.panelsOpen.at("Tracts"));
  EXPECT_FALSE(centres.count("Open")) << "the Data panel is closed";
  EXPECT_TRUE(centres.count("Load tracts")) << "the Tracts panel is open";
}

// The View panel's UI scale: the slider sends its value when let go (the font atlas is rebuilt once, not
// per drag step); the checkbox goes back to the monitor's scale.
TEST_F(ViewHeadlessUi, UiScaleSliderSendsTheScaleWhenLetGo) {
  state.uiScale = 1;
  state.uiScaleAuto = true;
  const auto scale = find<SetUiScale>(click("UI scale"));
  ASSERT_TRUE(scale);
  EXPECT_NEAR(scale->scale, 1.75, 0.15) << "the middle of 0.5..3";
  state.uiScaleAuto = false;
  const auto automatic = find<SetUiScale>(click("UI scale auto"));
  ASSERT_TRUE(automatic);
  EXPECT_EQ(automatic->scale, 0);
}

TEST_F(ViewTractsPanel, RegionsAreAddedAtTheCrosshairListedSavedAndTheCountShown) {
  state.crosshair = glm::dvec3(18, 3.7, 21.6);
  buffers.roiKind = 1; // exclude
  buffers.roiSizeMm = 7;
  open();
  const auto sphere = find<RoiAdd>(click("sphere at crosshair"));
  ASSERT_TRUE(sphere);
  EXPECT_EQ(sphere->kind, surfaces::RegionKind::Exclude);
  EXPECT_TRUE(sphere->spec.empty());
  EXPECT_EQ(sphere->region.shape, surfaces::RegionShape::Sphere);
  EXPECT_EQ(sphere->region.centre, state.crosshair);
  EXPECT_DOUBLE_EQ(sphere->region.radius, 7.0);
  const auto box = find<RoiAdd>(click("box at crosshair"));
  ASSERT_TRUE(box);
  EXPECT_EQ(box->region.shape, surfaces::RegionShape::Box);
  EXPECT_EQ(box->region.lo, state.crosshair - glm::dvec3(7));
  EXPECT_EQ(box->region.hi, state.crosshair + glm::dvec3(7));
  // The place mode waits for a click in a slice pane (the window's).
  click("place sphere");
  EXPECT_EQ(buffers.roiPlace, 1);
  // With a region: the rules for the set, its file and the selected streamlines.
  surfaces::Region r;
  r.centre = state.crosshair;
  r.radius = 6;
  r.name = "CST low";
  state.roiSet.regions.push_back(r);
  state.roiVisible = {1};
  state.roiActive = true;
  state.roiSelected = 40;
  const auto ends = find<RoiEndsOnly>(click("end points only"));
  ASSERT_TRUE(ends);
  EXPECT_TRUE(ends->on);
  const auto dim = find<RoiHideOthers>(click("hide the others (else dimmed)"));
  ASSERT_TRUE(dim);
  EXPECT_FALSE(dim->on);
  std::snprintf(buffers.roiPath.data(), buffers.roiPath.size(), "out/set.json");
  const auto save = find<SaveRegions>(click("save regions"));
  ASSERT_TRUE(save);
  EXPECT_EQ(save->path, "out/set.json");
  std::snprintf(buffers.roiSelectedPath.data(), buffers.roiSelectedPath.size(), "out/all.trx");
  std::snprintf(buffers.roiGroup.data(), buffers.roiGroup.size(), "cst");
  const auto selected = find<SaveTracts>(click("save selected"));
  ASSERT_TRUE(selected);
  EXPECT_TRUE(selected->selected);
  EXPECT_EQ(selected->asGroup, "cst");
  EXPECT_EQ(selected->path, "out/all.trx");
}
