// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view` in a real GLFW window under Xvfb, driven by scripts: panels drawn, screenshots written,
// the FA slider, slice keys and split view change what is on screen. Skips without xvfb-run unless
// DTF_REQUIRE_GL=1. Each test runs the viewer once at 640x480 on the bundled brain phantom.
#include "io/formats/png_io.h"
#include "io/formats/tracts.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <gtest/gtest.h>

namespace fs = std::filesystem;
using dtf::Image;

namespace {

const fs::path kSample = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

// Runs the viewer on `input` (the phantom by default) with `script` under Xvfb.
dtf::test::CliResult runViewer(const fs::path& scratch, const std::string& script,
                               const std::string& extra = "", const fs::path& input = kSample) {
  return dtf::test::runViewerScript(scratch, script, "'" + input.string() + "' " + extra);
}

std::string shot(const fs::path& scratch, const char* name) {
  return (scratch / name).string();
}

// Fraction of pixels of the rectangle [x0, x1) x [y0, y1) that pass `test`.
template <typename F> double fraction(const Image& img, int x0, int y0, int x1, int y1, F test) {
  std::size_t n = 0, total = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++total) {
      const auto* p = img.pixel(x, y);
      if (test(p[0], p[1], p[2])) ++n;
    }
  return total ? double(n) / total : 0;
}

bool lit(int r, int g, int b) {
  return r + g + b > 60;
}

} // namespace

TEST(ViewWindow, PanelsAndScreenshotsAreWritten) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r = runViewer(dir, "fa 0.25\nscreenshot " + shot(dir, "window.png") + "\nscreenshot-scene " +
                                    shot(dir, "scene.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image win = dtf::io::readPng(shot(dir, "window.png"));
  const Image scene = dtf::io::readPng(shot(dir, "scene.png"));
  ASSERT_EQ(win.width, 640);
  ASSERT_EQ(win.height, 480);
  // The scene is the window minus the 300 px side bar and the 26 px status bar.
  EXPECT_EQ(scene.width, 340);
  EXPECT_EQ(scene.height, 454);
  // Side bar: ImGui's blue collapsing headers and sliders, and light text.
  const double blue =
      fraction(win, 0, 0, 300, 454, [](int r_, int g, int b) { return b > 90 && b > r_ + 40 && b > g + 20; });
  const double text =
      fraction(win, 0, 0, 300, 454, [](int r_, int g, int b) { return r_ > 180 && g > 180 && b > 180; });
  EXPECT_GT(blue, 0.01) << "no panel headers in the side bar";
  EXPECT_GT(text, 0.01) << "no panel text in the side bar";
  // Status bar: its own background, not the scene's.
  EXPECT_GT(fraction(win, 0, 460, 640, 478, [](int r_, int g, int b) { return r_ + g + b > 15; }), 0.5);
  // The fabric covers part of the scene, and the window shows the same pixels there.
  const double covered = fraction(scene, 0, 0, scene.width, scene.height, lit);
  EXPECT_GT(covered, 0.05);
  EXPECT_LT(covered, 0.9);
  std::size_t same = 0;
  for (int y = 40; y < 400; ++y)
    for (int x = 40; x < 300; ++x)
      same += std::equal(scene.pixel(x, y), scene.pixel(x, y) + 3, win.pixel(x + 300, y));
  EXPECT_GT(same, 0.9 * 360 * 260) << "the window's scene area is not the scene screenshot";
}

TEST(ViewWindow, FaSliderSweepChangesTheSurface) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r = runViewer(dir, "fa 0.2\nscreenshot-scene " + shot(dir, "fa02.png") +
                                    "\nfa 0.4\nscreenshot-scene " + shot(dir, "fa04.png") +
                                    "\nfa 0.2\nscreenshot-scene " + shot(dir, "fa02b.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image a = dtf::io::readPng(shot(dir, "fa02.png")), b = dtf::io::readPng(shot(dir, "fa04.png"));
  const Image c = dtf::io::readPng(shot(dir, "fa02b.png"));
  const double changed = dtf::test::differingFraction(a, b);
  EXPECT_GT(changed, 0.01) << "FA 0.2 and 0.4 look the same";
  // Sweeping back restores the first surface (same mesh, same camera: the fabric converges to the same
  // image).
  EXPECT_LT(dtf::test::differingFraction(a, c), 0.5 * changed);
}

TEST(ViewWindow, SliceKeysMoveTheSlice) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r =
      // The paper's look: the phantom's isotropic tissue carries the fabric (the anatomy look shows its FA 0).
      runViewer(dir, "set look plain\nkey A\nscreenshot-scene " + shot(dir, "s0.png") + "\nkey PgUp\nscreenshot-scene " +
                         shot(dir, "s1.png") + "\nkey Down\nkey Down\nscreenshot-scene " +
                         shot(dir, "s2.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image s0 = dtf::io::readPng(shot(dir, "s0.png")), s1 = dtf::io::readPng(shot(dir, "s1.png"));
  const Image s2 = dtf::io::readPng(shot(dir, "s2.png"));
  EXPECT_GT(fraction(s0, 0, 0, s0.width, s0.height, lit), 0.1) << "the axial slice fills much of the view";
  EXPECT_GT(dtf::test::differingFraction(s0, s1), 0.05) << "PgUp did not move the slice";
  EXPECT_GT(dtf::test::differingFraction(s1, s2), 0.01) << "Down did not move the slice";
}

TEST(ViewWindow, SplitViewShowsTwoPanes) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r =
      runViewer(dir, "set look plain\nkey C\nscreenshot-scene " + shot(dir, "one.png") + "\nsplit on\nscreenshot-scene " +
                         shot(dir, "two.png") + "\nscreenshot " + shot(dir, "two_window.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image one = dtf::io::readPng(shot(dir, "one.png")), two = dtf::io::readPng(shot(dir, "two.png"));
  const int half = two.width / 2;
  const double left = fraction(two, 0, 0, half, two.height, lit);
  const double right = fraction(two, half, 0, two.width, two.height, lit);
  EXPECT_GT(left, 0.05);
  EXPECT_GT(right, 0.05);
  // Linked cameras: both panes show the slice at the same place, in different colour modes.
  EXPECT_NEAR(left, right, 0.2 * std::max(left, right));
  std::size_t sameColour = 0, coveredBoth = 0;
  for (int y = 0; y < two.height; ++y)
    for (int x = 0; x < half; ++x) {
      const auto *p = two.pixel(x, y), *q = two.pixel(x + half, y);
      if (!lit(p[0], p[1], p[2]) || !lit(q[0], q[1], q[2])) continue;
      ++coveredBoth;
      sameColour += std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) < 30;
    }
  EXPECT_GT(coveredBoth, 1000u);
  EXPECT_LT(sameColour, 0.7 * coveredBoth) << "the second pane should use the other colour mode";
  EXPECT_GT(dtf::test::differingFraction(one, two), 0.05) << "split did not change the scene";
}

TEST(ViewWindow, RuntimeErrorShowsModalAndExitCode2) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r =
      runViewer(dir, "load /nonexistent/brain.nii.gz\nscreenshot " + shot(dir, "error.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("script.txt:1: error: while loading /nonexistent/brain.nii.gz"), std::string::npos)
      << r.err;
  // The viewer kept running: the screenshot after the error was written.
  const Image win = dtf::io::readPng(shot(dir, "error.png"));
  EXPECT_EQ(win.width, 640);
}

TEST(ViewWindow, TractsAreLoadedAndCounted) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const auto r = runViewer(dir, "tracts " + tck.string() + "\nwait 2\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto at = r.err.find(tck.string() + ": ");
  ASSERT_NE(at, std::string::npos) << r.err;
  const long count = std::strtol(r.err.c_str() + at + tck.string().size() + 2, nullptr, 10);
  EXPECT_GT(count, 100) << r.err;
}

TEST(ViewWindow, ProbeReportsTheVoxelUnderThePixel) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  // The phantom: 48^3 voxels of 3.5 mm, RAS, voxel 0 at -82.25 mm. Axial view, scene 340x454: its centre
  // lies on the middle axial slice (k = 24, z = 1.75 mm), then on slice 30 (z = 22.75 mm).
  const auto r = runViewer(dir, "key A\nprobe 170 227\nprobe 2 2\nslice axial 30\nprobe 170 227\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto line = [&](int n) {
    const std::string tag = "script.txt:" + std::to_string(n) + ": probe ";
    const auto at = r.err.find(tag);
    return at == std::string::npos ? std::string() : r.err.substr(at, r.err.find('\n', at) - at);
  };
  double x = 0, y = 0, z = 0;
  int i = 0, j = 0, k = 0;
  ASSERT_EQ(std::sscanf(line(2).c_str(),
                        "script.txt:2: probe 170 227: surface at %lf %lf %lf mm, voxel %d %d %d", &x, &y, &z,
                        &i, &j, &k),
            6)
      << r.err;
  EXPECT_NEAR(z, 1.75, 0.2);
  EXPECT_EQ(k, 24);
  EXPECT_NEAR(x, -82.25 + 3.5 * i, 1.75 + 1e-6);
  EXPECT_NEAR(y, -82.25 + 3.5 * j, 1.75 + 1e-6);
  EXPECT_NE(line(3).find("background"), std::string::npos) << r.err;
  ASSERT_EQ(std::sscanf(line(5).c_str(),
                        "script.txt:5: probe 170 227: surface at %lf %lf %lf mm, voxel %d %d %d", &x, &y, &z,
                        &i, &j, &k),
            6)
      << r.err;
  EXPECT_NEAR(z, 22.75, 0.2);
  EXPECT_EQ(k, 30);
}

TEST(ViewWindow, ResizeKeepsTheFabricCoherent) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto r =
      runViewer(dir, "fa 0.25\nscreenshot-scene " + shot(dir, "small.png") +
                         "\nresize 900x700\nscreenshot-scene " + shot(dir, "large.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image small = dtf::io::readPng(shot(dir, "small.png")),
              large = dtf::io::readPng(shot(dir, "large.png"));
  ASSERT_EQ(large.width, 600);  // 900 - 300 px side bar
  ASSERT_EQ(large.height, 674); // 700 - 26 px status bar
  // The orthographic view keeps its height in mm: the surface grows with the scene height, in area by
  // (674 / 454)^2 = 2.2, and the fabric covers it as before.
  const double smallPixels =
      fraction(small, 0, 0, small.width, small.height, lit) * small.width * small.height;
  const double largePixels =
      fraction(large, 0, 0, large.width, large.height, lit) * large.width * large.height;
  EXPECT_NEAR(largePixels / smallPixels, 2.2, 0.4);
}

TEST(ViewWindow, SavedCameraRestoresTheSameImage) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const std::string cam = (dir / "view.camera").string();
  const auto r =
      runViewer(dir, "fa 0.25\nscreenshot-scene " + shot(dir, "a.png") + "\ncamera-save " + cam +
                         "\nrotate 90 0\nscreenshot-scene " + shot(dir, "b.png") + "\ncamera-load " + cam +
                         "\nscreenshot-scene " + shot(dir, "c.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Image a = dtf::io::readPng(shot(dir, "a.png")), b = dtf::io::readPng(shot(dir, "b.png"));
  const Image c = dtf::io::readPng(shot(dir, "c.png"));
  EXPECT_GT(dtf::test::differingFraction(a, b), 0.02) << "rotating did not change the view";
  // Same camera, same mesh: the still fabric starts from the same noise and converges to the same image.
  EXPECT_LT(dtf::test::differingFraction(a, c), 0.005);
}

TEST(ViewWindow, TractsOverTheRealBrainShowHideAndSplit) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const auto r = runViewer(
      dir,
      "slice axial 22\nscreenshot-scene " + shot(dir, "plain.png") + "\ntracts " + tck.string() +
          "\nscreenshot-scene " + shot(dir, "tracts.png") + "\ntracts-visible off\nscreenshot-scene " +
          shot(dir, "hidden.png") + "\ntracts-visible on\nsplit tracts\nscreenshot-scene " +
          shot(dir, "split.png") + "\ntracts-visible off\nscreenshot-scene " + shot(dir, "split_hidden.png") +
          "\ntracts-visible on\nscreenshot " + shot(dir, "window.png") + "\nquit\n",
      "", tensor);
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("tracts shown: 2000 streamline pieces, 147545 points (slab around the plane)"),
            std::string::npos)
      << r.err;
  const Image plain = dtf::io::readPng(shot(dir, "plain.png")),
              tracts = dtf::io::readPng(shot(dir, "tracts.png"));
  const Image hidden = dtf::io::readPng(shot(dir, "hidden.png"));
  const std::size_t drawn = dtf::test::tractPixels(tracts, plain);
  EXPECT_GT(drawn, 3000u) << "DEC-coloured tracts over the fabric";
  EXPECT_LT(dtf::test::tractPixels(hidden, plain), drawn / 50) << "hidden tracts left pixels behind";
  const Image split = dtf::io::readPng(shot(dir, "split.png"));
  const Image splitHidden = dtf::io::readPng(shot(dir, "split_hidden.png"));
  const std::size_t panes = dtf::test::paneDifference(split);
  EXPECT_GT(panes, 1500u) << "fabric | fabric + tracts: the right pane carries the tracts";
  EXPECT_LT(dtf::test::paneDifference(splitHidden), panes / 20)
      << "without tracts both panes show the same fabric";
}

TEST(ViewWindow, ScriptTracksComparesAndRefusesToOverwrite) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const std::string out = (dir / "tracked.tck").string();
  const auto r =
      runViewer(dir,
                "slice axial 22\nscreenshot-scene " + shot(dir, "plain.png") + "\ntracts " + tck.string() +
                    "\nagreement\ntrack from=slice:axial:22 select=100\nscreenshot-scene " +
                    shot(dir, "tracked.png") + "\ntracts-save " + out + "\ntracts-save " + out + "\nquit\n",
                "", tensor);
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  // The second save fails (exit code 2) naming the file; the viewer went on to `quit`.
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("script.txt:8: error: " + out + " exists (use --force to overwrite it"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("tracked 100 streamlines"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("wrote " + out), std::string::npos) << r.err;
  EXPECT_EQ(dtf::io::readTck(out).lineCount(), 100u);
  // The agreement printed for the slice is `dtfabric compare`'s.
  const dtf::test::CompareRun c = dtf::test::runCompare(tensor, tck, "slice=axial:22", dir);
  ASSERT_EQ(c.cli.exitCode, 0) << c.cli.err;
  ASSERT_TRUE(c.complete) << c.cli.out;
  char expected[200];
  std::snprintf(expected, sizeof expected, "agreement: %zu points compared, ", c.points);
  const auto at = r.err.find(expected);
  ASSERT_NE(at, std::string::npos) << r.err << "\nexpected " << expected;
  std::snprintf(expected, sizeof expected, "mean %.4f deg, median %.4f deg, below 15 deg %.6f", c.mean,
                c.median, c.below);
  EXPECT_NE(r.err.find(expected, at), std::string::npos) << r.err << "\nexpected " << expected;
  // The tracked streamlines are drawn over the slice.
  EXPECT_GT(dtf::test::tractPixels(dtf::io::readPng(shot(dir, "tracked.png")),
                                   dtf::io::readPng(shot(dir, "plain.png"))),
            1000u);
}

TEST(ViewWindow, TrackCancelStopsALongRun) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const auto dir = dtf::test::scratchDir();
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = runViewer(dir, "track from=fa:0.2 select=5000000\ntrack-cancel\nwait 2\nquit\n", "", tensor);
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("tracking cancelled after"), std::string::npos) << r.err;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 100.0);
}
