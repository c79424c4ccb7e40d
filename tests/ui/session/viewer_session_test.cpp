// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer's session without a window and without a GL context (this test links dtf_session only: no ImGui,
// no GLFW): loading with the layout diagnosis, surface specs and their extraction on the worker, the
// write/overwrite policy, errors into the modal's chain, fibre sets with their Fibres panel state and the
// probe's text for a known voxel of the crossing phantom.
#include "ui/session/tract_files.h"
#include "ui/session/viewer_session.h"
#include "io/formats/fibre_io.h"
#include "io/phantoms.h"
#include "io/formats/tensor_io.h"
#include "io/model/log.h"
#include "support/test_env.h"
#include "ui/session/tract_overlay.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <mutex>
#include <thread>

using namespace dtf;
using dtf::session::ViewerSession;

namespace {

// Takes the workers' results until nothing is queued or running (a bound far above the work's length).
void settle(ViewerSession& s) {
  const auto t0 = std::chrono::steady_clock::now();
  do {
    s.update();
    if (s.settled()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  } while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120));
  ASSERT_TRUE(s.settled()) << "the session's work did not end";
}

std::string constantTensors(const std::filesystem::path& dir) {
  io::PhantomOptions o;
  o.size = 16;
  o.spacing = 2.0;
  const std::string path = (dir / "constant.nii.gz").string();
  io::writeTensorVolume(path, io::makePhantom("constant", o).tensors, io::TensorLayout::Fsl);
  return path;
}

// The crossing phantom (60 degrees: bundles at -30 and +30 degrees from +x in the axial plane) as MRtrix
// peaks on an LAS grid, so the reader's frame handling is part of what the probe shows.
std::string crossingPeaks(const std::filesystem::path& dir) {
  io::PhantomOptions o;
  o.size = 24;
  o.crossingDeg = 60;
  o.las = true;
  const std::string path = (dir / "crossing_peaks.nii.gz").string();
  io::writeFibres(path, io::makeFibrePhantom("crossing", o), io::FibreLayout::MrtrixPeaks);
  return path;
}

bool mentions(const std::vector<std::string>& chain, const std::string& text) {
  for (const auto& link : chain)
    if (link.find(text) != std::string::npos) return true;
  return false;
}

} // namespace

TEST(ViewerSession, LoadsATensorVolumeWithItsLayoutAndExtractsTheFirstSurface) {
  const auto dir = test::scratchDir();
  const std::string path = constantTensors(dir);
  ViewerSession s("slice=axial:3");
  s.apply(session::LoadFile{path});
  EXPECT_TRUE(s.state().busy);
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_TRUE(st.hasData);
  EXPECT_FALSE(st.busy);
  EXPECT_EQ(st.data.path, path);
  EXPECT_EQ(st.data.layout, "fsl");
  EXPECT_FALSE(st.data.layoutReason.empty());
  EXPECT_EQ(st.data.dims, glm::ivec3(16));
  EXPECT_EQ(st.data.validVoxels, 16u * 16u * 16u);
  EXPECT_FALSE(st.fibres.present);
  EXPECT_EQ(st.surface, session::SurfaceKind::Axial);
  EXPECT_EQ(st.slice[0], 3); // the command line's index is kept
  EXPECT_EQ(s.loadSerial(), 1u);
  EXPECT_EQ(s.fieldSerial(), 1u);
  ASSERT_TRUE(s.mesh());
  EXPECT_GT(st.triangles, 0u);
  // The slice lies in the plane of voxel k = 3.
  const double z = s.dataset()->loaded.field.grid.toWorld(glm::dvec3(0, 0, 3)).z;
  glm::vec3 lo, hi;
  s.mesh()->bounds(lo, hi);
  EXPECT_NEAR(lo.z, z, 1e-3);
  EXPECT_NEAR(hi.z, z, 1e-3);
  EXPECT_EQ(s.homeView(), render::StandardView::Axial);
  EXPECT_EQ(st.recent.front(), path);
}

TEST(ViewerSession, ChangingTheSurfaceSpecExtractsAgainAndTheLatestRequestWins) {
  const auto dir = test::scratchDir();
  const std::string path = constantTensors(dir);
  ViewerSession s("slice=axial");
  s.apply(session::LoadFile{path});
  settle(s);
  const std::uint64_t meshes = s.meshSerial();
  s.apply(session::SetSurfaceSpec{"slice=coronal:5"});
  EXPECT_TRUE(s.state().surfacePending);
  settle(s);
  EXPECT_EQ(s.state().surface, session::SurfaceKind::Coronal);
  EXPECT_EQ(s.state().slice[1], 5);
  EXPECT_GT(s.meshSerial(), meshes);
  EXPECT_FALSE(s.state().surfacePending);
  EXPECT_NE(s.state().surfaceText.find("coronal"), std::string::npos) << s.state().surfaceText;
  // A burst of slice requests (a dragged slider): the surface on screen is the last one asked for.
  for (int k = 0; k < 12; ++k)
    s.apply(session::SetSlice{0, k});
  settle(s);
  EXPECT_EQ(s.state().slice[0], 11);
  const double z = s.dataset()->loaded.field.grid.toWorld(glm::dvec3(0, 0, 11)).z;
  glm::vec3 lo, hi;
  s.mesh()->bounds(lo, hi);
  EXPECT_NEAR(lo.z, z, 1e-3);
  EXPECT_NEAR(hi.z, z, 1e-3);
  // The field is uploaded once: surfaces do not change it.
  EXPECT_EQ(s.fieldSerial(), 1u);
}

TEST(ViewerSession, NeverWritesOverAnInputAndAsksOrRefusesBeforeReplacingAFile) {
  const auto dir = test::scratchDir();
  const std::string input = constantTensors(dir);
  ViewerSession s("slice=axial");
  s.apply(session::LoadFile{input});
  settle(s);
  const session::Action shot = session::Screenshot{input};
  // An input: refused even with force, into the error modal.
  EXPECT_FALSE(s.mayWrite(input, true, shot));
  ASSERT_FALSE(s.state().errorChain.empty());
  EXPECT_TRUE(mentions(s.state().errorChain, input));
  s.apply(session::DismissError{});
  EXPECT_TRUE(s.state().errorChain.empty());
  // Saving tracts over an input is refused the same way (the tract path goes through the same policy).
  const std::string existing = (dir / "existing.png").string();
  std::ofstream(existing) << "x";
  const std::string fresh = (dir / "fresh.png").string();
  EXPECT_TRUE(s.mayWrite(fresh, false, session::Screenshot{fresh}));
  EXPECT_TRUE(s.mayWrite(existing, true, session::Screenshot{existing}));
  // A script (no prompt): an existing file without force is refused.
  s.setAskBeforeOverwrite(false);
  const std::uint64_t errors = s.errorSerial();
  EXPECT_FALSE(s.mayWrite(existing, false, session::Screenshot{existing}));
  EXPECT_EQ(s.errorSerial(), errors + 1);
  EXPECT_TRUE(mentions(s.state().errorChain, "exists"));
  s.apply(session::DismissError{});
  // The GUI: the prompt holds the action; "overwrite" gives it back with force, "cancel" drops it.
  s.setAskBeforeOverwrite(true);
  EXPECT_FALSE(s.mayWrite(existing, false, session::SaveCamera{existing}));
  EXPECT_EQ(s.state().overwritePath, existing);
  EXPECT_TRUE(s.state().errorChain.empty());
  const auto forced = s.answerOverwrite(true);
  ASSERT_TRUE(forced.has_value());
  ASSERT_TRUE(std::holds_alternative<session::SaveCamera>(*forced));
  EXPECT_TRUE(std::get<session::SaveCamera>(*forced).force);
  EXPECT_TRUE(s.state().overwritePath.empty());
  EXPECT_FALSE(s.mayWrite(existing, false, session::Screenshot{existing}));
  EXPECT_FALSE(s.answerOverwrite(false).has_value());
  EXPECT_TRUE(s.state().overwritePath.empty());
  // Files read by other means (the script, a mesh) count as inputs too.
  s.addInput(existing);
  EXPECT_FALSE(s.mayWrite(existing, true, session::Screenshot{existing}));
  // Nothing was written by any of this.
  std::ifstream in(existing);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "x");
  EXPECT_FALSE(std::filesystem::exists(fresh));
}

TEST(ViewerSession, ErrorsBecomeTheModalsChainAndLeaveTheSessionUsable) {
  const auto dir = test::scratchDir();
  ViewerSession s("slice=axial");
  const std::string missing = (dir / "missing.nii.gz").string();
  s.apply(session::LoadFile{missing});
  settle(s);
  ASSERT_FALSE(s.state().errorChain.empty());
  EXPECT_EQ(s.state().errorChain.front(), "while loading " + missing);
  EXPECT_FALSE(s.state().hasData);
  EXPECT_FALSE(s.state().busy);
  // Bad values are refused where they are given, with the reason.
  s.apply(session::DismissError{});
  s.apply(session::LoadFile{missing, "no-such-layout"});
  EXPECT_TRUE(mentions(s.state().errorChain, "no-such-layout"));
  s.apply(session::SetTractsNear{-1});
  EXPECT_TRUE(mentions(s.state().errorChain, "tract distance"));
  s.apply(session::SaveTracts{(dir / "t.tck").string()});
  EXPECT_TRUE(mentions(s.state().errorChain, "no tracts to save"));
  s.apply(session::TrackTracts{});
  EXPECT_TRUE(mentions(s.state().errorChain, "load a tensor volume"));
  // After the errors a good file loads.
  s.apply(session::DismissError{});
  const std::string good = constantTensors(dir);
  s.apply(session::LoadFile{good});
  settle(s);
  EXPECT_TRUE(s.state().errorChain.empty()) << s.state().errorChain.back();
  EXPECT_TRUE(s.state().hasData);
  // A surface that cannot be built keeps the previous one on screen and says why.
  ASSERT_TRUE(s.mesh());
  const std::uint64_t meshes = s.meshSerial();
  s.apply(session::SetSurfaceSpec{"mesh=" + (dir / "no_mesh.ply").string()});
  settle(s);
  EXPECT_TRUE(mentions(s.state().errorChain, "no_mesh.ply"));
  EXPECT_EQ(s.meshSerial(), meshes);
  EXPECT_TRUE(s.mesh());
}

TEST(ViewerSession, LoadsAFibreSetWithItsLayoutAndProbesBothPopulationsOfTheCrossing) {
  const auto dir = test::scratchDir();
  const std::string peaks = crossingPeaks(dir);
  ViewerSession s;
  s.apply(session::LoadFile{peaks});
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  ASSERT_TRUE(st.fibres.present);
  EXPECT_EQ(st.fibres.layout, "mrtrix-peaks");
  EXPECT_EQ(st.data.layout, "mrtrix-peaks");
  EXPECT_FALSE(st.fibres.layoutReason.empty());
  EXPECT_EQ(st.fibres.slots, 2);
  EXPECT_TRUE(st.fibres.faSource.empty()); // no tensor paired, none in the file
  EXPECT_EQ(st.fabric.colour, render::ColourMode::Fibres);
  // Without FA the default FA isosurface gives way to the middle axial slice.
  EXPECT_EQ(st.surface, session::SurfaceKind::Axial);
  ASSERT_TRUE(s.mesh());
  // Both bundles alone (one population) and their overlap (two) are counted at the threshold in effect.
  EXPECT_GT(st.fibres.populations[0], 0u);
  EXPECT_GT(st.fibres.populations[1], 0u);
  EXPECT_EQ(st.fibres.populations[2], 0u);
  EXPECT_EQ(st.fibres.populations[0] + st.fibres.populations[1], st.fibres.voxels);
  EXPECT_FLOAT_EQ(st.fibres.threshold, render::FabricParams{}.fibreThreshold);

  // The voxel at the world origin lies in the overlap: both directions, in world RAS, whatever the grid.
  s.probeAt(glm::dvec3(0.0));
  const session::ProbeInfo& p = st.probe;
  ASSERT_TRUE(p.inData);
  EXPECT_FALSE(p.hasTensor);
  ASSERT_EQ(p.fibres.size(), 2u);
  const double c = std::cos(M_PI / 6), sn = std::sin(M_PI / 6);
  const glm::vec3 a(c, sn, 0), b(c, -sn, 0);
  const bool aFirst =
      std::abs(glm::dot(p.fibres[0].direction, a)) > std::abs(glm::dot(p.fibres[0].direction, b));
  EXPECT_GT(std::abs(glm::dot(p.fibres[aFirst ? 0 : 1].direction, a)), 0.999f);
  EXPECT_GT(std::abs(glm::dot(p.fibres[aFirst ? 1 : 0].direction, b)), 0.999f);
  for (const auto& f : p.fibres) {
    EXPECT_NEAR(f.amplitude, 0.4f, 1e-4f);
    EXPECT_TRUE(f.drawn);
  }
  EXPECT_NE(p.text.find("fibres: ("), std::string::npos) << p.text;
  EXPECT_NE(p.text.find("amplitude 0.4"), std::string::npos) << p.text;
  EXPECT_EQ(p.text.find("FA"), std::string::npos) << p.text; // no tensor, no FA shown

  // Outside the bundles: no fibre.
  const Grid& g = s.dataset()->loaded.field.grid;
  s.probeAt(g.toWorld(glm::dvec3(0, 0, 12)));
  EXPECT_FALSE(st.probe.inData);

  // The threshold is the option table's fibre-threshold: a new value recounts the populations.
  render::FabricParams params = st.fabric;
  params.fibreThreshold = 0.5f;
  s.apply(session::SetFabricParams{params});
  EXPECT_FLOAT_EQ(st.fibres.threshold, 0.5f);
  // A tensor colour mode is refused for a fibre set; the fibres mode stays.
  params.colour = render::ColourMode::Medical;
  s.apply(session::SetFabricParams{params});
  EXPECT_TRUE(mentions(st.errorChain, "fibres colour mode"));
  EXPECT_EQ(st.fabric.colour, render::ColourMode::Fibres);
  s.apply(session::DismissError{});
  // Surfaces that need FA are refused with the reason, the slice stays on screen.
  const std::uint64_t meshes = s.meshSerial();
  s.apply(session::SetFaThreshold{0.3});
  settle(s);
  EXPECT_TRUE(mentions(st.errorChain, "needs FA")) << (st.errorChain.empty() ? "" : st.errorChain.back());
  EXPECT_EQ(s.meshSerial(), meshes);
}

TEST(ViewerSession, AFibreSetWithAPairedTensorHasFaAndTheTensorInTheProbe) {
  const auto dir = test::scratchDir();
  io::PhantomOptions o;
  o.size = 24;
  o.crossingDeg = 60;
  const std::string peaks = (dir / "peaks_ras.nii.gz").string(), tensor = (dir / "tensor.nii.gz").string();
  io::writeFibres(peaks, io::makeFibrePhantom("crossing", o), io::FibreLayout::DipyPeaks);
  io::writeTensorVolume(tensor, io::makePhantom("crossing", o).tensors, io::TensorLayout::Fsl);
  ViewerSession s("slice=axial");
  s.apply(session::LoadFile{peaks, "dipy-peaks", tensor});
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_EQ(st.fibres.layout, "dipy-peaks");
  EXPECT_EQ(st.fibres.faSource, tensor);
  EXPECT_FALSE(s.mayWrite(tensor, true, session::Screenshot{tensor})); // the paired tensor is an input too
  s.apply(session::DismissError{});
  s.probeAt(glm::dvec3(0.0));
  ASSERT_TRUE(st.probe.inData);
  EXPECT_TRUE(st.probe.hasTensor);
  EXPECT_EQ(st.probe.fibres.size(), 2u);
  EXPECT_NE(st.probe.text.find("FA "), std::string::npos) << st.probe.text;
  EXPECT_NE(st.probe.text.find("fibres: ("), std::string::npos) << st.probe.text;
  // With FA an isosurface can be built.
  s.apply(session::SetFaThreshold{0.2});
  settle(s);
  EXPECT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_EQ(st.surface, session::SurfaceKind::FaIsosurface);
}

TEST(ViewerSession, TheFibresColourModeFollowsTheDataButKeepsAChoiceMadeForTensors) {
  const auto dir = test::scratchDir();
  const std::string peaks = crossingPeaks(dir), tensors = constantTensors(dir);
  ViewerSession s("slice=axial");
  s.apply(session::LoadFile{peaks});
  settle(s);
  EXPECT_EQ(s.state().fabric.colour, render::ColourMode::Fibres);
  s.apply(session::LoadFile{tensors});
  settle(s);
  EXPECT_FALSE(s.state().fibres.present);
  EXPECT_EQ(s.state().fabric.colour, render::ColourMode::Medical); // back to the tensors' default
  // A tensor shown the fibre way (its principal direction) stays so for the next tensor file.
  render::FabricParams p = s.state().fabric;
  p.colour = render::ColourMode::Fibres;
  s.apply(session::SetFabricParams{p});
  EXPECT_TRUE(s.state().errorChain.empty());
  s.apply(session::LoadFile{tensors});
  settle(s);
  EXPECT_EQ(s.state().fabric.colour, render::ColourMode::Fibres);
  EXPECT_EQ(s.loadSerial(), 3u);
}

TEST(ViewerSession, TractsAreLoadedSelectedForTheSurfaceAndSavedWithoutGl) {
  const auto dir = test::scratchDir();
  const std::string tensors = constantTensors(dir); // 16 voxels of 2 mm: world -15..15 mm
  // Lines along x through the volume at several heights z; the axial slice through z = 1 mm selects a slab.
  Polylines lines;
  lines.offsets = {0};
  for (int i = 0; i < 8; ++i) {
    for (int k = -12; k <= 12; ++k)
      lines.points.emplace_back(float(k), 0.0f, float(4 * i - 14));
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  const std::string tck = (dir / "lines.tck").string();
  session::writeTracts(tck, lines, nullptr);
  ViewerSession s("slice=axial");
  s.apply(session::LoadFile{tensors});
  settle(s);
  s.apply(session::LoadTracts{tck});
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_EQ(st.tractCount, 8u);
  EXPECT_EQ(st.tractPoints, 8u * 25u);
  EXPECT_NEAR(st.tractMeanLengthMm, 24.0, 1e-3);
  ASSERT_TRUE(s.tractDisplay());
  EXPECT_GT(s.displaySerial(), 0u);
  // A planar surface shows every tract, clipped to a slab around its plane (drawn by the front end).
  EXPECT_TRUE(s.tractsSlab());
  EXPECT_TRUE(st.tractsSlab);
  EXPECT_EQ(st.tractsShownLines, 8u);
  EXPECT_NEAR(std::abs(s.tractsPlane().z), 1.0f, 1e-5f);
  // The tract file is an input: saving over it is refused even with force; a new file is written.
  s.apply(session::SaveTracts{tck, true});
  EXPECT_TRUE(mentions(st.errorChain, tck));
  s.apply(session::DismissError{});
  const std::string out = (dir / "saved.tck").string();
  s.apply(session::SaveTracts{out});
  settle(s);
  EXPECT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_EQ(st.saveStatus, "wrote " + out);
  EXPECT_EQ(session::readTracts(out).lineCount(), 8u);
  // Width and clip-slab changes count for the front end's drawing.
  const std::uint64_t style = s.tractStyleSerial();
  s.apply(session::SetTractWidth{3.0});
  s.apply(session::SetTractsClip{2.0, 1.0});
  EXPECT_EQ(s.tractStyleSerial(), style + 2);
  s.apply(session::SetTractWidth{0.0});
  EXPECT_TRUE(mentions(st.errorChain, "tract width"));
}

TEST(ViewerSession, AnFaSurfaceNamedForAFibreSetWithoutFaIsRefusedWithTheReason) {
  const auto dir = test::scratchDir();
  ViewerSession s("fa=0.3");
  s.apply(session::LoadFile{crossingPeaks(dir)});
  settle(s);
  EXPECT_TRUE(s.state().hasData);
  EXPECT_FALSE(s.mesh());
  EXPECT_TRUE(mentions(s.state().errorChain, "needs FA"))
      << (s.state().errorChain.empty() ? "" : s.state().errorChain.back());
}

// The ROI selection of the session (ui/session/roi_selection.h) on lines with a known answer: eight lines
// along x at heights z = -14, -10, ..., 14 mm, x from -12 to 12 mm in 1 mm steps.
TEST(ViewerSession, RegionsSelectOffTheUiThreadAndTheSelectionIsDrawnSavedAndPublished) {
  const auto dir = test::scratchDir();
  Polylines lines;
  lines.offsets = {0};
  for (int i = 0; i < 8; ++i) {
    for (int k = -12; k <= 12; ++k)
      lines.points.emplace_back(float(k), 0.0f, float(4 * i - 14));
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  const std::string tck = (dir / "lines.tck").string();
  session::writeTracts(tck, lines, nullptr);
  ViewerSession s("slice=axial");
  s.apply(session::LoadTracts{tck});
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  // No region: every streamline counts as selected, the selection is not active.
  const session::RoiSelection& roi = s.roiSelection();
  EXPECT_FALSE(roi.active);
  EXPECT_EQ(roi.count(), 8u);
  EXPECT_EQ(roi.tracts.get(), s.tracts());
  const std::uint64_t g0 = roi.generation;

  // A sphere of radius 3 at z = -4 holds vertices of the lines at z = -6 and z = -2 (distance 2), not
  // z = -10 or 2 (6): lines 2 and 3.
  session::RoiAdd add;
  add.spec = "0,0,-4,3";
  s.apply(add);
  EXPECT_TRUE(s.roiSelection().pending);
  settle(s);
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  EXPECT_TRUE(s.roiSelection().active);
  EXPECT_GT(s.roiSelection().generation, g0);
  ASSERT_TRUE(s.roiSelection().lines);
  EXPECT_EQ(*s.roiSelection().lines, (std::vector<std::uint32_t>{2, 3}));
  EXPECT_EQ(st.roiSelected, 2u);
  EXPECT_EQ(st.roiSet.regions.size(), 1u);
  EXPECT_EQ(st.roiSet.regions[0].name, "0,0,-4,3");
  // Hidden: the overlay draws the two selected lines only; dimmed: all eight, the others grey.
  ASSERT_TRUE(s.shownTracts());
  EXPECT_EQ(s.shownTracts()->lineCount(), 2u);
  s.apply(session::RoiHideOthers{false});
  settle(s);
  ASSERT_EQ(s.shownTracts()->lineCount(), 8u);
  const auto& pp = s.shownTracts()->perPoint;
  const auto colours = std::find_if(pp.begin(), pp.end(), [](const TractValues& v) {
    return v.name == render::kTractDisplayColours;
  });
  ASSERT_NE(colours, pp.end());
  EXPECT_EQ(colours->values[2 * 25 * 4 + 3], 0.0f) << "a selected line keeps its DEC colour";
  EXPECT_EQ(colours->values[0 * 25 * 4 + 3], 1.0f) << "a line left out is grey";
  EXPECT_NEAR(colours->values[0], 0.3f, 1e-6f);
  // An exclude box on line 3 (z = -2) leaves line 2.
  session::RoiAdd ex;
  ex.kind = surfaces::RegionKind::Exclude;
  ex.spec = "box:-20,-1,-3,20,1,-1";
  s.apply(ex);
  settle(s);
  EXPECT_EQ(*s.roiSelection().lines, (std::vector<std::uint32_t>{2}));
  // Ends only: line 2's end points (x = +-12, z = -6) are 12.2 mm from the sphere's centre: nothing is kept.
  s.apply(session::RoiEndsOnly{true});
  settle(s);
  EXPECT_TRUE(s.roiSelection().active);
  EXPECT_TRUE(s.roiSelection().lines->empty());
  s.apply(session::RoiEndsOnly{false});
  settle(s);
  // The selected streamlines are written as `select` writes them; the region set saved and read back.
  const std::string out = (dir / "selected.tck").string(), json = (dir / "set.json").string();
  s.apply(session::SaveTracts{out, false, true});
  s.apply(session::SaveRegions{json});
  settle(s);
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  const Polylines saved = session::readTracts(out);
  ASSERT_EQ(saved.lineCount(), 1u);
  EXPECT_EQ(saved.points.front(), glm::vec3(-12, 0, -6));
  // As a group of a .trx holding every streamline (`select --as-group`), on the grid of the data on screen
  // (none yet: refused, naming the file); a .tck cannot hold a group.
  const std::string trx = (dir / "grouped.trx").string();
  session::SaveTracts grouped{trx, false, true};
  grouped.asGroup = "picked";
  s.apply(grouped);
  EXPECT_TRUE(mentions(st.errorChain, trx + ": a .trx file needs a loaded tensor volume"));
  s.apply(session::DismissError{});
  s.apply(session::LoadFile{constantTensors(dir)});
  settle(s);
  s.apply(grouped);
  settle(s);
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.back();
  const Polylines all = session::readTracts(trx);
  EXPECT_EQ(all.lineCount(), 8u);
  ASSERT_EQ(all.groups.size(), 1u);
  EXPECT_EQ(all.groups[0].name, "picked");
  EXPECT_EQ(all.groups[0].lines, (std::vector<std::uint32_t>{2}));
  grouped.path = (dir / "grouped.tck").string();
  s.apply(grouped);
  EXPECT_TRUE(mentions(st.errorChain, "needs a .trx output"));
  s.apply(session::DismissError{});
  s.apply(session::RoiClear{});
  settle(s);
  EXPECT_FALSE(s.roiSelection().active);
  EXPECT_EQ(s.shownTracts()->lineCount(), 8u);
  s.apply(session::LoadRegions{json});
  settle(s);
  EXPECT_EQ(st.roiSet.regions.size(), 2u);
  EXPECT_EQ(*s.roiSelection().lines, (std::vector<std::uint32_t>{2}));
  // Removing the exclude region gives lines 2 and 3 again; a bad spec names itself and changes nothing.
  s.apply(session::RoiRemove{1});
  settle(s);
  EXPECT_EQ(*s.roiSelection().lines, (std::vector<std::uint32_t>{2, 3}));
  session::RoiAdd bad;
  bad.spec = "0,0,0,-3";
  s.apply(bad);
  EXPECT_TRUE(mentions(st.errorChain, "0,0,0,-3")) << (st.errorChain.empty() ? "" : st.errorChain.back());
  EXPECT_EQ(st.roiSet.regions.size(), 1u);
  s.apply(session::DismissError{});
  // The region file is an input now: saving over it is refused.
  s.apply(session::SaveRegions{json, true});
  EXPECT_TRUE(mentions(st.errorChain, json));
}

// After a region change near a curved surface the overlay draws a quick pass first (every 2nd streamline of
// the selection measured: 200 k points > kNearSurfaceQuickPointCap), then the full pass, which ends as the
// library's selection of every selected streamline. The surface: a sphere of radius 8 mm (the isosurface of
// |x|); the lines: 4000 lines of 50 points along x (-30..30 mm), |y|, |z| <= 10 mm.
TEST(ViewerSession, ARegionChangeNearACurvedSurfaceDrawsAQuickPassThenTheFullOne) {
  const auto dir = test::scratchDir();
  io::PhantomOptions o;
  o.size = 24;
  const io::Phantom sphere = io::makePhantom("sphere", o);
  const std::string tensors = (dir / "sphere.nii.gz").string(), radius = (dir / "r.nii").string();
  io::writeTensorVolume(tensors, sphere.tensors, io::TensorLayout::Fsl);
  io::writeScalarVolume(radius, sphere.scalar);
  Polylines lines;
  lines.offsets = {0};
  for (int i = 0; i < 4000; ++i) {
    const float y = -10.0f + 20.0f * float(i % 63) / 62.0f, z = -10.0f + 20.0f * float(i / 63) / 63.0f;
    for (int k = 0; k < 50; ++k)
      lines.points.emplace_back(-30.0f + 60.0f * float(k) / 49.0f, y, z);
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  ASSERT_GT(lines.points.size(), session::kNearSurfaceQuickPointCap);
  const std::string tck = (dir / "lines.tck").string();
  session::writeTracts(tck, lines, nullptr);
  ViewerSession s("iso=" + radius + ":8");
  s.apply(session::LoadFile{tensors});
  settle(s);
  s.apply(session::LoadTracts{tck});
  settle(s);
  const session::ViewerState& st = s.state();
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  ASSERT_TRUE(s.mesh());
  std::vector<std::string> shown;
  std::mutex m;
  setLogSink([&](LogLevel, const std::string& text) {
    std::lock_guard<std::mutex> lock(m);
    if (text.rfind("tracts shown:", 0) == 0) shown.push_back(text);
  });
  session::RoiAdd add;
  add.spec = "0,0,0,30"; // every line
  s.apply(add);
  settle(s);
  setLogSink(nullptr);
  ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
  ASSERT_EQ(shown.size(), 2u);
  EXPECT_NE(shown[0].find("of every 2nd streamline"), std::string::npos) << shown[0];
  EXPECT_EQ(shown[1].find("of every"), std::string::npos) << shown[1];
  const session::TractSelection full = session::selectTracts(lines, *s.mesh(), st.tractsNearMm);
  EXPECT_EQ(full.lineStep, 1u);
  EXPECT_GT(full.near.points.size(), 1000u);
  EXPECT_LT(full.near.points.size(), lines.points.size() / 2);
  EXPECT_EQ(st.tractsShownPoints, session::tractOverlayDisplay(full.near).points.size());
}

// A colouring, a group choice, the dimming of the streamlines a region leaves out and the profile's nodes
// are made on the tract worker past the sync size (here 0: always), and end as the same tracts as when made
// at once; until the worker's result comes the tracts on screen stay. A missing name is refused at once
// either way. Eight lines along x at heights z = -14, -10, ..., 14 mm with a per-point value (x) and a
// group of the first four.
TEST(ViewerSession, AChoiceMadeOnTheWorkerEqualsTheOneMadeAtOnce) {
  const auto dir = test::scratchDir();
  Polylines lines;
  lines.offsets = {0};
  TractValues x{"x", 1, {}};
  for (int i = 0; i < 8; ++i) {
    for (int k = -12; k <= 12; ++k) {
      lines.points.emplace_back(float(k), 0.0f, float(4 * i - 14));
      x.values.push_back(float(k));
    }
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  lines.perPoint.push_back(x);
  lines.groups.push_back({"low", {0, 1, 2, 3}});
  const std::string tensors = constantTensors(dir);
  const std::string trx = (dir / "lines.trx").string();
  const Grid grid = io::readTensorVolume(tensors).field.grid;
  session::writeTracts(trx, lines, &grid);
  std::vector<Polylines> results[2];
  for (const bool onWorker : {false, true}) {
    SCOPED_TRACE(onWorker);
    ViewerSession s("slice=axial");
    if (onWorker) s.setTractChoiceSyncPoints(0);
    s.apply(session::LoadTracts{trx});
    settle(s);
    const session::ViewerState& st = s.state();
    ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
    auto step = [&](const session::Action& a) {
      const Polylines* before = s.shownTracts();
      s.apply(a);
      ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
      if (onWorker) {
        EXPECT_EQ(s.shownTracts(), before) << "made on the worker: the tracts on screen stay";
      }
      settle(s);
      ASSERT_TRUE(st.errorChain.empty()) << st.errorChain.front();
      EXPECT_NE(s.shownTracts(), before);
      results[onWorker].push_back(*s.shownTracts());
    };
    session::SetTractColour colour;
    colour.value = "x";
    step(colour);
    EXPECT_DOUBLE_EQ(st.tractColourLo, -12.0);
    EXPECT_DOUBLE_EQ(st.tractColourHi, 12.0);
    session::SetTractGroups low;
    low.all = false;
    low.shown = {"low"};
    step(low);
    session::SetTractGroups all;
    step(all);
    session::RoiAdd add;
    add.spec = "0,0,-4,3";
    s.apply(add);
    settle(s);
    step(session::RoiHideOthers{false});
    session::SetTractColour node;
    node.value = "node";
    step(node);
    // Names the tracts do not hold are refused at once, and the choice on screen stays.
    session::SetTractColour missing;
    missing.value = "nope";
    s.apply(missing);
    EXPECT_TRUE(mentions(st.errorChain, "no per-point or per-streamline data 'nope'"));
    s.apply(session::DismissError{});
    session::SetTractGroups none;
    none.all = false;
    none.shown = {"nope"};
    s.apply(none);
    EXPECT_TRUE(mentions(st.errorChain, "no group 'nope'"));
    s.apply(session::DismissError{});
    settle(s);
    EXPECT_EQ(st.tractColourBy, "node");
  }
  ASSERT_EQ(results[0].size(), 5u);
  ASSERT_EQ(results[1].size(), results[0].size());
  for (std::size_t i = 0; i < results[0].size(); ++i) {
    SCOPED_TRACE(i);
    const Polylines &a = results[0][i], &b = results[1][i];
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.perPoint.size(), b.perPoint.size());
    for (std::size_t d = 0; d < a.perPoint.size(); ++d) {
      EXPECT_EQ(a.perPoint[d].name, b.perPoint[d].name);
      EXPECT_EQ(a.perPoint[d].values, b.perPoint[d].values);
    }
  }
  EXPECT_EQ(results[0][1].lineCount(), 4u) << "the group of the first four";
  EXPECT_EQ(results[0][3].lineCount(), 8u) << "dimmed, not hidden";
}
