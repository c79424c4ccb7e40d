// SPDX-License-Identifier: GPL-3.0-or-later
// Tracts in the viewer scene (app/viewer/viewer.h), headless: drawn over the fabric and hidden on request, the
// selection redone for each surface, the split mode "fabric | fabric + tracts", tracking, saving and the
// agreement measure on the worker threads, each checked against the command line that does the same
// (`dtfabric compare`, `dtfabric track`) or against the library call. Real brain: the shared
// iu_prisma_dwi tensors and their 2000 deterministic streamlines.
#include "app/viewer/viewer.h"
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/model/error.h"
#include "render/tract_renderer.h"
#include "support/cli.h"
#include "support/gl_test.h"
#include "support/view_scene.h"
#include "support/window.h"
#include "surfaces/analyses/near_surface.h"
#include "surfaces/analyses/tract_profile.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tract_colouring.h"
#include "ui/session/tract_files.h"

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <thread>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kW = 256, kH = 256;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using Scene = test::ViewScene;

// Pixels of the rectangle [x0, x1) x [0, h) whose colour differs by more than 40 in some channel.
std::size_t differing(const Image& a, const Image& b, int x0 = 0, int x1 = -1) {
  if (x1 < 0) x1 = a.width;
  std::size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto *p = a.pixel(x, y), *q = b.pixel(x, y);
      n += std::abs(p[0] - q[0]) > 40 || std::abs(p[1] - q[1]) > 40 || std::abs(p[2] - q[2]) > 40;
    }
  return n;
}

// The right corticospinal tract of the shared tracts, cut with two spheres by `dtfabric select` into `dir`.
fs::path cutCst(const fs::path& tck, const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path cst = dir / "cst.tck";
  const test::CliResult r = test::runDtfabric("select '" + tck.string() + "' -o '" + cst.string() +
                                                  "' --include 18,3.7,21.6,6 --include 20,0,45,10 --force",
                                              dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  return cst;
}

#define BRAIN_FILES()                                                                                        \
  DTF_GL_TEST_SETUP();                                                                                       \
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");                                        \
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck")

} // namespace

TEST(ViewTracts, DrawnOverTheFabricHiddenOnRequestAndSplitFabricVersusTracts) {
  BRAIN_FILES();
  Scene s("slice=axial:22");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const Image plain = s.image();
  s.apply(session::LoadTracts{tck.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.state().tractCount, 2000u);
  EXPECT_TRUE(s.state().tractsSlab) << "a slice: every tract, clipped to a slab around it";
  const Image tracts = s.image();
  const std::size_t drawn = dtf::test::tractPixels(tracts, plain);
  EXPECT_GT(drawn, 2000u) << "DEC-coloured tract pixels over the fabric";
  // A thin slab keeps fewer of them.
  s.apply(session::SetTractsNear{0.5});
  s.converge();
  EXPECT_LT(dtf::test::tractPixels(s.image(), plain), drawn * 3 / 4);
  s.apply(session::SetTractsNear{3.0});
  s.apply(session::SetTractsVisible{false});
  s.converge();
  const Image hidden = s.image();
  EXPECT_LT(dtf::test::tractPixels(hidden, plain), drawn / 50) << "hidden tracts left pixels behind";
  s.apply(session::SetTractsVisible{true});
  s.converge();
  EXPECT_LT(differing(s.image(), tracts), tracts.rgba.size() / 4 / 100)
      << "showing them again restores the image";

  // Split "fabric | fabric + tracts": one camera, the same fabric in the same colour mode, so the panes
  // differ by the tracts alone, and not at all once they are hidden.
  using dtf::test::paneDifference;
  s.apply(session::SetSplit{true, session::SecondPane::Tracts});
  s.converge();
  const Image split = s.image();
  io::writePng((test::scratchDir() / "split.png").string(), split);
  const std::size_t withTracts = paneDifference(split);
  EXPECT_GT(withTracts, 500u) << "the right pane carries the tracts";
  s.apply(session::SetTractsVisible{false});
  s.converge();
  EXPECT_LT(paneDifference(s.image()), withTracts / 20) << "without tracts both panes show the same fabric";
  s.apply(session::SetTractsVisible{true});
  s.converge();
  EXPECT_FALSE(s.scene.paneShowsTracts(0));
  EXPECT_TRUE(s.scene.paneShowsTracts(1));
}

TEST(ViewTracts, SelectionFollowsTheSurfaceAndEqualsTheLibrarySelection) {
  BRAIN_FILES();
  Scene s("fa=0.3");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{tck.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_FALSE(s.state().tractsSlab);
  const TensorField field = io::readTensorVolume(tensor.string()).field;
  const Polylines all = session::readTracts(tck.string());
  const ScalarVolume fa = computeFaMap(field);
  auto expected = [&](double t, double near) {
    const Mesh m = session::buildSurface(session::parseSurfaceSpec("fa=" + std::to_string(t)), field, fa);
    return surfaces::selectNearSurface(all, surfaces::DistanceQuery(m), near).points.size();
  };
  const std::size_t at03 = s.state().tractsShownPoints;
  EXPECT_EQ(at03, expected(0.3, 3.0));
  s.apply(session::SetFaThreshold{0.2});
  s.converge();
  EXPECT_EQ(s.state().tractsShownPoints, expected(0.2, 3.0));
  EXPECT_NE(s.state().tractsShownPoints, at03);
  s.apply(session::SetTractsNear{1.5});
  s.converge();
  EXPECT_EQ(s.state().tractsShownPoints, expected(0.2, 1.5));
  s.apply(session::SetTractsNear{0});
  s.converge();
  EXPECT_EQ(s.state().tractsShownPoints, all.points.size()) << "0 mm: every tract";
}

// The clip slab for dense tractograms around a curved surface: it faces the camera, sits at the surface's
// centre, moves with its depth, and lets nothing through once it lies beyond the data.
TEST(ViewTracts, ClipSlabThinsTheTractsFollowsItsDepthAndTurnsOff) {
  BRAIN_FILES();
  Scene s("fa=0.25");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const Image plain = s.image();
  s.apply(session::LoadTracts{tck.string()});
  s.apply(session::SetTractsNear{0}); // every tract: the case the clip is for
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_FALSE(s.state().tractsSlab);
  const Image all = s.image();
  const std::size_t allDrawn = dtf::test::tractPixels(all, plain);
  ASSERT_GT(allDrawn, 3000u);

  s.apply(session::SetTractsClip{4.0, 0.0});
  s.converge();
  const Image centre = s.image();
  io::writePng((test::scratchDir() / "clip_centre.png").string(), centre);
  const std::size_t centreDrawn = dtf::test::tractPixels(centre, plain);
  EXPECT_LT(centreDrawn, allDrawn * 2 / 3) << "an 8 mm slab keeps a part of a whole-brain tractogram";
  EXPECT_GT(centreDrawn, allDrawn / 50) << "the slab through the centre of the brain cuts tracts";

  s.apply(session::SetTractsClip{4.0, 25.0});
  s.converge();
  const Image deeper = s.image();
  EXPECT_GT(dtf::test::tractPixels(deeper, plain), allDrawn / 100);
  EXPECT_GT(differing(deeper, centre), centreDrawn / 4) << "another depth shows other tracts";

  s.apply(session::SetTractsClip{4.0, 200.0}); // beyond the brain along the view
  s.converge();
  EXPECT_LT(dtf::test::tractPixels(s.image(), plain), allDrawn / 200)
      << "a slab outside the data shows no tract";

  s.apply(session::SetTractsClip{0.0, 200.0});
  s.converge();
  EXPECT_LT(differing(s.image(), all), all.rgba.size() / 4 / 100) << "0 mm turns the clip off";
  EXPECT_EQ(s.state().tractsShownPoints, session::readTracts(tck.string()).points.size())
      << "the clip is for display: the selection keeps every point";
}

TEST(ViewTracts, AgreementMatchesTheCompareCommand) {
  BRAIN_FILES();
  Scene s("fa=0.25");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{tck.string()});
  s.converge();
  const auto dir = test::scratchDir();
  for (const char* surface : {"fa=0.25", "slice=axial:22"}) {
    SCOPED_TRACE(surface);
    s.apply(session::SetSurfaceSpec{surface});
    s.apply(session::ComputeAgreement{2.0, 9});
    s.converge();
    ASSERT_EQ(s.lastError(), "");
    ASSERT_TRUE(s.state().hasAgreement);
    const test::CompareRun c = test::runCompare(tensor, tck, surface, dir);
    ASSERT_EQ(c.cli.exitCode, 0) << c.cli.err;
    ASSERT_TRUE(c.complete) << c.cli.out;
    const session::ViewerState& v = s.state();
    EXPECT_EQ(v.agreementPoints, c.points);
    EXPECT_NEAR(v.agreementMeanDeg, c.mean, 1e-4);
    EXPECT_NEAR(v.agreementMedianDeg, c.median, 1e-4);
    EXPECT_NEAR(v.agreementFracBelow15, c.below, 1e-6);
    std::string histogram;
    for (float h : v.agreementHistogram)
      histogram += (histogram.empty() ? "" : ", ") + std::to_string(int(h));
    EXPECT_NE(c.cli.out.find("\"histogram\": [" + histogram + "]"), std::string::npos) << histogram << "\n"
                                                                                       << c.cli.out;
  }
}

TEST(ViewTracts, TrackingMatchesTheTrackCommandAndSavingWritesEveryPoint) {
  BRAIN_FILES();
  Scene s("slice=axial:22");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.converge();
  session::TrackRequest r;
  r.seeds = session::SeedKind::Slice;
  r.sliceAxis = 0;
  r.sliceIndex = -1; // the slice on screen: 22
  r.number = 150;
  s.apply(session::TrackTracts{r});
  EXPECT_TRUE(s.state().tracking);
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_FALSE(s.state().tracking);
  EXPECT_EQ(s.state().tractCount, 150u) << s.state().trackStatus;
  const auto dir = test::scratchDir();
  const auto viewer = dir / "viewer.tck", cli = dir / "cli.tck";
  s.apply(session::SaveTracts{viewer.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_EQ(s.state().saveStatus, "wrote " + viewer.string());
  const auto t = test::runDtfabric(
      "track '" + tensor.string() + "' --seed-slice axial:22 --select 150 -o '" + cli.string() + "'", dir);
  ASSERT_EQ(t.exitCode, 0) << t.err;
  const Polylines a = io::readTck(viewer.string()), b = io::readTck(cli.string());
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.points, b.points) << "same seeds and options: the same streamlines";

  // An existing file is not replaced unless asked: scripts fail naming it, the window asks first.
  const auto before = fs::file_size(viewer);
  s.scene.setAskBeforeOverwrite(false); // as under --script
  s.apply(session::SaveTracts{viewer.string()});
  EXPECT_NE(s.lastError().find(viewer.string() + " exists"), std::string::npos) << s.lastError();
  s.apply(session::DismissError{});
  s.scene.setAskBeforeOverwrite(true);
  s.apply(session::SaveTracts{viewer.string()});
  EXPECT_EQ(s.state().overwritePath, viewer.string());
  EXPECT_EQ(s.lastError(), "");
  s.apply(session::ConfirmOverwrite{false}); // Cancel: nothing written
  EXPECT_EQ(s.state().overwritePath, "");
  fs::resize_file(viewer, 10);
  s.apply(session::SaveTracts{viewer.string()});
  s.apply(session::ConfirmOverwrite{true}); // Overwrite
  EXPECT_EQ(s.state().overwritePath, "");
  s.converge();
  EXPECT_EQ(s.lastError(), "");
  EXPECT_EQ(fs::file_size(viewer), before) << "the prompt's Overwrite rewrote the file";
  // Only tract files.
  s.apply(session::SaveTracts{tensor.string(), true});
  EXPECT_NE(s.lastError().find("tract files end in .tck, .trk or .vtk"), std::string::npos) << s.lastError();
}

TEST(ViewTracts, TrackingCanBeCancelledAndBadInputIsAnErrorNamingTheFile) {
  BRAIN_FILES();
  Scene s("slice=axial:22");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{tck.string()});
  s.converge();
  session::TrackRequest r;
  r.seeds = session::SeedKind::FaMask;
  r.faMask = 0.2;
  r.number = 5'000'000; // minutes of work
  s.apply(session::TrackTracts{r});
  const auto t0 = Clock::now();
  while (s.state().trackSeedsDone == 0 && secondsSince(t0) < 30) {
    s.frame();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_GT(s.state().trackSeedsDone, 0u) << "progress is reported while tracking";
  EXPECT_GT(s.state().trackProgress, 0.0);
  s.apply(session::TrackTracts{r});
  EXPECT_NE(s.lastError().find("tracking is already running"), std::string::npos) << s.lastError();
  s.apply(session::DismissError{});
  const auto c0 = Clock::now();
  s.apply(session::CancelTracking{});
  s.converge();
  EXPECT_LT(secondsSince(c0), 20.0);
  EXPECT_NE(s.state().trackStatus.find("tracking cancelled"), std::string::npos) << s.state().trackStatus;
  EXPECT_EQ(s.state().tractPath, tck.string()) << "a cancelled run keeps the tracts on screen";
  EXPECT_EQ(s.state().tractCount, 2000u);
  // The loaded file is an input: never overwritten, whatever the flags.
  s.apply(session::SaveTracts{tck.string(), true});
  EXPECT_EQ(s.lastError(), "refusing to write " + tck.string() + ": it is an input file");
  s.apply(session::DismissError{});

  const auto dir = test::scratchDir();
  const auto bad = dir / "broken.tck";
  std::ofstream(bad) << "mrtrix tracks\nfile: . 20\ndatatype: Float32LE\nEND\n";
  s.apply(session::LoadTracts{bad.string()});
  s.converge();
  ASSERT_FALSE(s.state().errorChain.empty());
  EXPECT_EQ(s.state().errorChain.front(), "while loading tracts " + bad.string());
  EXPECT_EQ(s.state().tractCount, 2000u) << "the previous tracts stay";
  s.apply(session::DismissError{});
  r = session::TrackRequest{};
  r.seeds = session::SeedKind::Sphere;
  r.centre = glm::dvec3(500, 500, 500); // outside the brain: no streamline
  r.number = 5;
  s.apply(session::TrackTracts{r});
  s.converge();
  ASSERT_FALSE(s.state().errorChain.empty());
  EXPECT_EQ(s.state().errorChain.front(), "while tracking");
  EXPECT_NE(s.lastError().find("no streamline passed"), std::string::npos) << s.lastError();
}

TEST(ViewTracts, AMillionPointsStayInteractiveAndEndComplete) {
  DTF_GL_TEST_SETUP();
  // 5000 helices of 200 points (1M) through the phantom's 168 mm cube.
  Polylines big;
  big.offsets = {0};
  for (int i = 0; i < 5000; ++i) {
    const float cx = float(i % 70) * 2.0f - 70.0f, cy = float(i / 70 % 70) * 2.0f - 70.0f;
    for (int k = 0; k < 200; ++k) {
      const float t = float(k) / 199.0f;
      big.points.emplace_back(cx + 3.0f * std::cos(12.0f * t + float(i)),
                              cy + 3.0f * std::sin(12.0f * t + float(i)), 120.0f * t - 60.0f);
    }
    big.offsets.push_back(static_cast<std::uint32_t>(big.points.size()));
  }
  const auto dir = test::scratchDir();
  io::writeTck((dir / "big.tck").string(), big);
  Scene s("slice=axial");
  s.apply(session::LoadFile{(test::sourceDir() / "sample_data" / "brain_phantom.nii.gz").string(), "auto"});
  s.apply(session::LoadTracts{(dir / "big.tck").string()});
  s.apply(session::SetTractsNear{0});
  s.converge(300);
  ASSERT_EQ(s.lastError(), "");
  ASSERT_NE(s.scene.tractRenderer(), nullptr);
  EXPECT_EQ(s.scene.tractRenderer()->pointCount(), 1'000'000u);
  EXPECT_EQ(s.state().tractsLevel, 0) << "still: every display point";
  EXPECT_DOUBLE_EQ(s.state().tractsLevelFraction, 1.0);
  // Moving: each frame draws what its budget allows, a coarser level or part of one.
  bool reduced = false;
  for (int i = 0; i < 8; ++i) {
    s.apply(session::Rotate{6, 0});
    s.frame();
    reduced |= s.state().tractsLevel > 0 || s.state().tractsLevelFraction < 1.0;
  }
  EXPECT_TRUE(reduced) << "1M points drawn whole while moving";
  EXPECT_GT(s.scene.tractBudget().msPerSegment(0), 0.0);
  s.converge(300);
  EXPECT_EQ(s.state().tractsLevel, 0);
  EXPECT_DOUBLE_EQ(s.state().tractsLevelFraction, 1.0);
}

// The Fabric panel's "along the tracts" (session::SetFabricAlong, `view --fabric-along`): the proximity
// weight of the tracts on screen (the right corticospinal tract) is built off the UI thread and reaches the
// pane's renderer, FA goes beneath, and the pixels away from the bundle show that FA grey instead of the
// fabric; off restores the fabric.
TEST(ViewTracts, TheFabricAlongTheTractsShowsFaAwayFromThem) {
  BRAIN_FILES();
  const fs::path cst = cutCst(tck, test::scratchDir() / "cst");
  Scene s("slice=coronal:33");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{cst.string()});
  s.apply(session::SetTractsVisible{false});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const Image fabric = s.image();
  EXPECT_FALSE(s.scene.paneRenderer(0).hasAlong());
  s.apply(session::SetFabricAlong{true, 1.0});
  EXPECT_TRUE(s.state().fabricAlong);
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  EXPECT_TRUE(s.scene.paneRenderer(0).hasAlong());
  EXPECT_EQ(s.state().background, "fa (the fabric along the tracts)");
  const Image along = s.image();
  io::writePng((test::scratchDir() / "fabric.png").string(), fabric);
  io::writePng((test::scratchDir() / "along.png").string(), along);
  const std::size_t changed = differing(along, fabric);
  EXPECT_GT(changed, 1000u) << "the fabric left the pixels away from the tracts";
  // Grey (FA) is what remains where it changed: r = g = b within rounding.
  std::size_t grey = 0, all = 0;
  for (int y = 0; y < along.height; ++y)
    for (int x = 0; x < along.width; ++x) {
      const auto *p = along.pixel(x, y), *q = fabric.pixel(x, y);
      if (std::abs(p[0] - q[0]) <= 40 && std::abs(p[1] - q[1]) <= 40 && std::abs(p[2] - q[2]) <= 40) continue;
      ++all;
      grey += std::abs(p[0] - p[1]) <= 2 && std::abs(p[1] - p[2]) <= 2;
    }
  EXPECT_GT(grey, all * 9 / 10) << grey << " of " << all;
  s.apply(session::SetFabricAlong{{}, -1.0});
  EXPECT_NE(s.lastError().find("(0, 1000] mm"), std::string::npos) << s.lastError();
  EXPECT_EQ(s.state().fabricAlongMm, 1.0) << "a bad distance changes nothing";
  s.apply(session::DismissError{});
  s.apply(session::SetFabricAlong{false, {}});
  s.converge();
  EXPECT_FALSE(s.scene.paneRenderer(0).hasAlong());
  EXPECT_LT(differing(s.image(), fabric), fabric.rgba.size() / 4 / 100) << "off: the fabric everywhere again";
}

// The Profile panel (session::SetProfile, HoverProfileNode): the right corticospinal tract cut from the
// tracts with two spheres (`dtfabric select`) is profiled along FA as `dtfabric profile` profiles it, and
// hovering node K puts the crosshair at the core position `dtfabric profile` reports for node K (within 1 mm;
// the same computation, so to rounding); a click pins it, and the crosshair returns there when the hover
// ends.
TEST(ViewTracts, HoveringAProfileNodePutsTheCrosshairAtItsCore) {
  BRAIN_FILES();
  const fs::path dir = test::scratchDir() / "view_profile";
  fs::create_directories(dir);
  const fs::path cst = cutCst(tck, dir), tsv = dir / "cst.tsv";
  const test::CliResult profile = test::runDtfabric("profile '" + cst.string() + "' --scalar fa --tensor '" +
                                                        tensor.string() + "' -o '" + tsv.string() + "'",
                                                    dir);
  ASSERT_EQ(profile.exitCode, 0) << profile.err;
  // node -> (x, y, z, mean) from the tidy table.
  std::map<int, std::array<double, 4>> rows;
  {
    std::istringstream in(test::readText(tsv));
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line.rfind("bundle\tscalar\tnode\tx\ty\tz\tmean", 0), 0u) << line;
    while (std::getline(in, line)) {
      std::istringstream f(line);
      std::string bundle, scalar;
      int node = 0;
      std::array<double, 4> v{};
      f >> bundle >> scalar >> node >> v[0] >> v[1] >> v[2] >> v[3];
      rows[node] = v;
    }
  }
  ASSERT_EQ(rows.size(), 100u);

  Scene s("slice=axial:22");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{cst.string()});
  s.apply(session::SetOrtho{true});
  s.apply(session::SetProfile{true, std::string("fa")});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const session::ViewerState::Profile& pr = s.state().profile;
  ASSERT_EQ(pr.error, "");
  ASSERT_EQ(pr.core.size(), 100u);
  EXPECT_EQ(pr.streamlines, 40u);
  EXPECT_EQ(pr.scalars, (std::vector<std::string>{"fa", "md", "ad", "rd"}));
  for (int k : {0, 37, 99}) {
    s.apply(session::HoverProfileNode{k, false});
    s.frame();
    ASSERT_EQ(s.lastError(), "");
    const glm::dvec3 want(rows[k][0], rows[k][1], rows[k][2]);
    EXPECT_LT(glm::distance(s.state().crosshair, want), 1.0) << "node " << k;
    EXPECT_NEAR(pr.mean[std::size_t(k)], rows[k][3], 1e-4) << "node " << k << ": the profile's FA";
  }
  s.apply(session::HoverProfileNode{37, true}); // pinned
  s.apply(session::HoverProfileNode{80, false});
  EXPECT_LT(glm::distance(s.state().crosshair, glm::dvec3(rows[80][0], rows[80][1], rows[80][2])), 1.0);
  s.apply(session::HoverProfileNode{-1, false}); // the hover ends: back to the pinned node
  EXPECT_EQ(pr.pinned, 37);
  EXPECT_LT(glm::distance(s.state().crosshair, glm::dvec3(rows[37][0], rows[37][1], rows[37][2])), 1.0);
  s.apply(session::HoverProfileNode{100, false});
  EXPECT_NE(s.lastError().find("100 nodes"), std::string::npos) << s.lastError();
  s.apply(session::DismissError{});

  // Any scalar image, as `dtfabric profile --scalar NAME=IMAGE`: the shared FA map gives the command's means.
  const fs::path faMap = tensor.parent_path() / "dti_FA.nii.gz", faTsv = dir / "fa_image.tsv";
  const test::CliResult image = test::runDtfabric(
      "profile '" + cst.string() + "' --scalar 'FA=" + faMap.string() + "' -o '" + faTsv.string() + "'", dir);
  ASSERT_EQ(image.exitCode, 0) << image.err;
  std::map<int, double> imageMean;
  {
    std::istringstream in(test::readText(faTsv));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::istringstream f(line);
      std::string bundle, scalar;
      int node = 0;
      double x = 0, y = 0, z = 0, mean = 0;
      f >> bundle >> scalar >> node >> x >> y >> z >> mean;
      EXPECT_EQ(scalar, "FA");
      imageMean[node] = mean;
    }
  }
  ASSERT_EQ(imageMean.size(), 100u);
  s.apply(session::SetProfile{{}, "FA=" + faMap.string()});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  ASSERT_EQ(pr.error, "");
  ASSERT_EQ(pr.mean.size(), 100u);
  for (int k : {0, 37, 99})
    EXPECT_NEAR(pr.mean[std::size_t(k)], imageMean[k], 1e-4) << "node " << k;
  s.apply(session::SetProfile{{}, std::string("FA=") + (dir / "missing.nii.gz").string()});
  EXPECT_NE(s.lastError().find("missing.nii.gz: no such file"), std::string::npos) << s.lastError();
  s.apply(session::SetProfile{{}, std::string("fb")});
  EXPECT_NE(s.lastError().find("NAME=IMAGE"), std::string::npos) << s.lastError();
}

// With regions, the fabric follows the selected streamlines: the whole tractogram with the two spheres that
// cut the right corticospinal tract shows exactly the image of that tract loaded alone; the profile too
// measures the selection (40 streamlines). A selection of nothing leaves no fabric.
TEST(ViewTracts, TheFabricAlongAndTheProfileFollowTheRoiSelection) {
  BRAIN_FILES();
  const fs::path cst = cutCst(tck, test::scratchDir() / "cst");
  Scene s("slice=coronal:33");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{cst.string()});
  s.apply(session::SetTractsVisible{false});
  s.apply(session::SetFabricAlong{true, 2.0});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const Image want = s.image(); // the CST loaded alone

  s.apply(session::LoadTracts{tck.string()});
  s.apply(session::SetProfile{true, {}});
  for (const char* spec : {"18,3.7,21.6,6", "20,0,45,10"}) {
    session::RoiAdd add;
    add.spec = spec;
    s.apply(add);
  }
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  ASSERT_EQ(s.scene.session().roiSelection().count(), 40u);
  EXPECT_EQ(s.state().profile.streamlines, 40u);
  EXPECT_EQ(differing(s.image(), want), 0u) << "the selection's fabric is the CST's";
  // A region that keeps nothing: no fabric anywhere, FA alone.
  session::RoiAdd none;
  none.spec = "box:200,200,200,201,201,201";
  s.apply(none);
  s.converge();
  ASSERT_EQ(s.scene.session().roiSelection().count(), 0u);
  const Image empty = s.image();
  std::size_t coloured = 0;
  for (int y = 0; y < empty.height; ++y)
    for (int x = 0; x < empty.width; ++x) {
      const auto* p = empty.pixel(x, y);
      coloured += std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 8;
    }
  EXPECT_LT(coloured, 20u) << "grey alone (the furniture's few coloured pixels aside)";
  EXPECT_NE(s.state().profile.error, "");
}

namespace {

// The pixel (column, row from the top) of a world point in pane 0 of a single-pane 256 x 256 scene.
glm::dvec2 pixelOf(const Scene& s, const glm::dvec3& world) {
  const render::Camera& c = s.scene.camera(0);
  const glm::dvec4 clip = c.projection(double(kW) / kH) * c.view() * glm::dvec4(world, 1.0);
  return {(clip.x / clip.w * 0.5 + 0.5) * kW, (0.5 - clip.y / clip.w * 0.5) * kH};
}

// Pixels within `r` of `at` in the highlight colour (render::TractStyle::highlightColour, drawn unlit).
int highlightedNear(const Image& img, glm::dvec2 at, int r) {
  int n = 0;
  for (int y = int(at.y) - r; y <= int(at.y) + r; ++y)
    for (int x = int(at.x) - r; x <= int(at.x) + r; ++x) {
      if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
      const auto* p = img.pixel(x, y);
      n += p[0] >= 250 && p[1] >= 250 && std::abs(p[2] - 64) <= 6;
    }
  return n;
}

} // namespace

// The right corticospinal tract (40 streamlines) seen from the front over the most posterior coronal slice,
// every streamline drawn. Hovering profile node K draws the points of node K (surfaces::nodePerPoint, the
// profile's orientation) in the highlight colour: pixels at node K's core position have it, pixels at the
// cores of nodes far from K do not, and every highlighted pixel lies within a few pixels of a node-K point
// (CPU reference: the points projected through the pane's camera). Then the tracts coloured by the profile:
// each point takes the colour map's colour of the profile's FA at its node (lit: the pixel's colour is a
// multiple of it).
TEST(ViewTracts, AHoveredProfileNodeIsABandAcrossTheBundleAndTractsTakeTheProfilesValue) {
  BRAIN_FILES();
  const fs::path dir = test::scratchDir();
  const fs::path cst = cutCst(tck, dir / "cst");
  const Polylines lines = session::readTracts(cst.string());
  const std::vector<float> node = surfaces::nodePerPoint(lines, nullptr, surfaces::ProfileOptions{});
  Scene s("slice=coronal:0");
  s.apply(session::LoadFile{tensor.string(), "auto"});
  s.apply(session::LoadTracts{cst.string()});
  s.apply(session::SetTractsNear{0.0});
  s.apply(session::SetTractWidth{3.0});
  s.apply(session::SetProfile{true, std::string("fa")});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const session::ViewerState::Profile& pr = s.state().profile;
  ASSERT_EQ(pr.core.size(), 100u);
  const Image plain = s.image();

  constexpr int kNode = 50;
  s.apply(session::HoverProfileNode{kNode, false});
  s.converge();
  const Image band = s.image();
  io::writePng((dir / "profile_plain.png").string(), plain);
  io::writePng((dir / "profile_band.png").string(), band);
  const glm::dvec2 core = pixelOf(s, pr.core[kNode]);
  EXPECT_GT(highlightedNear(band, core, 3), 0)
      << "at node " << kNode << "'s core " << core.x << "," << core.y;
  EXPECT_EQ(highlightedNear(plain, core, 3), 0) << "nothing highlighted before the hover";
  for (int far : {5, 20, 80, 95})
    EXPECT_EQ(highlightedNear(band, pixelOf(s, pr.core[std::size_t(far)]), 3), 0) << "node " << far;
  // Every highlighted pixel near a point of nodes K - 1 .. K + 1 (the band's default half-width is one node;
  // it reaches halfway to the neighbouring points).
  std::vector<glm::dvec2> atNode;
  for (std::size_t i = 0; i < node.size(); ++i)
    if (std::abs(node[i] - float(kNode)) <= 1.0f) atNode.push_back(pixelOf(s, glm::dvec3(lines.points[i])));
  ASSERT_FALSE(atNode.empty());
  int highlighted = 0, far = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (highlightedNear(band, {x + 0.5, y + 0.5}, 0) == 0) continue;
      ++highlighted;
      double d = 1e9;
      for (const glm::dvec2& p : atNode)
        d = std::min(d, glm::distance(p, glm::dvec2(x + 0.5, y + 0.5)));
      far += d > 6.0;
    }
  EXPECT_GE(highlighted, 10); // the bundle is about 100 px tall here: 3 nodes are 2-3 px
  EXPECT_EQ(far, 0) << "of " << highlighted << " highlighted pixels";
  // The hover ends: the band goes.
  s.apply(session::HoverProfileNode{-1, false});
  s.converge();
  EXPECT_EQ(differing(s.image(), plain), 0u);

  // Coloured by the profile's value, over the profile's own range.
  s.apply(session::SetTractColour{session::kProfileColouring, {}});
  s.converge();
  ASSERT_EQ(s.lastError(), "");
  const Image byProfile = s.image();
  io::writePng((dir / "profile_coloured.png").string(), byProfile);
  double lo = 1e9, hi = -1e9;
  for (double v : pr.mean)
    lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_DOUBLE_EQ(s.state().tractColourLo, lo);
  EXPECT_DOUBLE_EQ(s.state().tractColourHi, hi);
  EXPECT_EQ(s.state().tractColourBy, "profile");
  // Per point of the tracts on screen: the pixel's colour against the colour of the profile's FA at the
  // point's node, by the angle between them as RGB vectors (lighting scales the colour).
  auto agreeing = [&](const Image& img) {
    int agree = 0, seen = 0;
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (!std::isfinite(node[i])) continue;
      const glm::dvec2 p = pixelOf(s, glm::dvec3(lines.points[i]));
      if (p.x < 0 || p.y < 0 || p.x >= kW || p.y >= kH) continue;
      const auto* px = img.pixel(int(p.x), int(p.y));
      const glm::dvec3 got(px[0], px[1], px[2]);
      const double mean = pr.mean[std::size_t(node[i])];
      const glm::dvec3 want(render::tractValueColour(float((mean - lo) / (hi - lo))));
      if (glm::length(got) < 30) continue; // too dark to say
      ++seen;
      const double cosine = glm::dot(glm::normalize(got), glm::normalize(want));
      agree += cosine > 0.98;
    }
    return std::make_pair(agree, seen);
  };
  const auto [agree, seen] = agreeing(byProfile);
  EXPECT_GT(seen, 200);
  EXPECT_GT(agree, seen * 3 / 4) << agree << " of " << seen;
  const auto [agreeDec, seenDec] = agreeing(plain);
  EXPECT_LT(agreeDec, seenDec / 10) << "DEC does not pass this test: " << agreeDec << " of " << seenDec;
  // render has no profile: the value is refused there.
  Polylines copy = lines;
  session::TractColouring c;
  c.value = session::kProfileColouring;
  EXPECT_THROW(session::applyTractColouring(copy, c, cst.string()), UsageError);
}
