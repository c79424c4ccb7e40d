// SPDX-License-Identifier: GPL-3.0-or-later
// Crossing fibres in the viewer under Xvfb: a fibre set written by `dtfabric phantom crossing` (MRtrix peaks
// on an LAS grid, so the frame handling is part of it) opens from a script line or as the view's INPUT with a
// paired tensor; the probe at the centre of the crossing lists both populations with their world directions,
// and the rendered centre of the crossing shows threads along both bundles (the orientation-histogram check
// of the fibre render tests), not along their tensor average. The whole window is kept for a look (Fibres
// section: file, layout, threshold, populations drawn).
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/orientation_histogram.h"
#include "support/test_env.h"
#include "support/window.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using dtf::Image;

namespace {

std::string shot(const fs::path& dir, const char* name) {
  return (dir / name).string();
}

// The probe line of script line `n`, from "probe X Y: " on.
std::string probeLine(const std::string& err, int n) {
  const std::string tag = "script.txt:" + std::to_string(n) + ": probe ";
  const auto at = err.find(tag);
  return at == std::string::npos ? std::string() : err.substr(at, err.find('\n', at) - at);
}

struct Listed {
  double x, y, z, amplitude;
};

// The fibres a probe line lists: "fibres: (X Y Z) amplitude A (R%)[, ...]".
std::vector<Listed> listedFibres(const std::string& line) {
  std::vector<Listed> out;
  auto at = line.find("fibres: ");
  if (at == std::string::npos) return out;
  at += 8;
  while (true) {
    Listed f{};
    if (std::sscanf(line.c_str() + at, " (%lf %lf %lf) amplitude %lf", &f.x, &f.y, &f.z, &f.amplitude) != 4)
      break;
    out.push_back(f);
    const auto next = line.find(", (", at);
    if (next == std::string::npos) break;
    at = next + 1;
  }
  return out;
}

// Both 60-degree bundles (at -30 and +30 degrees from +x in the axial plane, world RAS) are listed.
void expectBothBundles(const std::vector<Listed>& fibres, const std::string& line) {
  ASSERT_EQ(fibres.size(), 2u) << line;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  int plus = 0, minus = 0;
  for (const auto& f : fibres) {
    EXPECT_NEAR(f.amplitude, 0.4, 1e-3) << line;
    EXPECT_NEAR(std::hypot(f.x, f.y, f.z), 1.0, 2e-3) << line;
    plus += std::abs(f.x * c + f.y * s) > 0.999;
    minus += std::abs(f.x * c - f.y * s) > 0.999;
  }
  EXPECT_EQ(plus, 1) << line;
  EXPECT_EQ(minus, 1) << line;
}

fs::path crossingPeaks(const fs::path& dir) {
  const fs::path peaks = dir / "crossing60_peaks.nii.gz";
  const auto r = dtf::test::runDtfabric(
      "phantom crossing --crossing 60 --grid las --layout mrtrix-peaks -o '" + peaks.string() + "'", dir);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  return peaks;
}

} // namespace

TEST(ViewFibresWindow, ScriptLoadsAFibreSetProbesBothPopulationsAndWeavesBothBundles) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const fs::path peaks = crossingPeaks(dir);
  // Without FA the viewer opens the middle axial slice; zoom 5 frames the centre of the crossing (about
  // 13 mm of the 64 mm phantom), where the two bundles overlap.
  const auto r = dtf::test::runViewerScript(
      dir, "fibres layout=mrtrix-peaks " + peaks.string() + "\nzoom 5\nprobe 170 227\nscreenshot-scene " +
               shot(dir, "fibres_scene.png") + "\nresize 640x1000\nscreenshot " +
               shot(dir, "fibres_window.png") + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string line = probeLine(r.err, 3);
  ASSERT_FALSE(line.empty()) << r.err;
  EXPECT_EQ(line.find("FA"), std::string::npos) << "no tensor paired: " << line;
  expectBothBundles(listedFibres(line), line);

  const Image img = dtf::io::readPng(shot(dir, "fibres_scene.png"));
  ASSERT_EQ(img.width, 340);
  ASSERT_EQ(img.height, 454);
  // The centre of the crossing: both bundles appear as threads (radiological view: the image mirrors x,
  // which maps the pair of bundle directions +-30 degrees onto itself).
  const auto h = dtf::test::orientationHistogram(img, 70, 127, 270, 327);
  const auto p = dtf::test::peaks(h, 0.3);
  std::string list;
  for (double x : p)
    list += std::to_string(x) + " ";
  EXPECT_LE(dtf::test::nearestPeak(p, 30.0), 6.0) << "peaks: " << list; // 3 bins of 2 degrees
  EXPECT_LE(dtf::test::nearestPeak(p, -30.0), 6.0) << "peaks: " << list;
  // Not on the tensor average (the bisector, 0 degrees): its bin stays below half of the bundles'. (No "no
  // peak near 0" check: the woven lattice of two crossing thread sets can leave a weak local maximum there.)
  EXPECT_LT(dtf::test::binValue(h, 0.0),
            0.5 * std::min(dtf::test::binValue(h, 30.0), dtf::test::binValue(h, -30.0)))
      << "peaks: " << list;
}

TEST(ViewFibresWindow, InputWithAPairedTensorProbesTheTensorAndTheFibresAndSplitsDtiBesideThem) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const fs::path peaks = crossingPeaks(dir), tensor = dir / "crossing60_tensor.nii.gz";
  const auto t =
      dtf::test::runDtfabric("phantom crossing --crossing 60 --grid las -o '" + tensor.string() + "'", dir);
  ASSERT_EQ(t.exitCode, 0) << t.err;
  const auto r = dtf::test::runViewerScript(
      dir,
      "slice axial 32\nprobe 170 227\nsplit colour\nzoom 5\nscreenshot-scene " +
          shot(dir, "fibres_split.png") + "\nscreenshot " + shot(dir, "fibres_split_window.png") +
          "\nset fibre-threshold 0.5\nwait 2\nquit\n",
      "'" + peaks.string() + "' --tensor '" + tensor.string() + "' --surface slice=axial");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string line = probeLine(r.err, 2);
  ASSERT_FALSE(line.empty()) << r.err;
  EXPECT_NE(line.find(", FA "), std::string::npos) << line; // the paired tensor's FA and e1
  expectBothBundles(listedFibres(line), line);
  // DTI beside the fibre set on the same surface and camera: the left pane weaves both bundles, the right
  // pane (the paired tensor's medical colours) weaves their average, the bisector at 0 degrees.
  const Image split = dtf::io::readPng(shot(dir, "fibres_split.png"));
  ASSERT_EQ(split.width, 340);
  const int y0 = split.height / 2 - 70, y1 = split.height / 2 + 70;
  const auto left = dtf::test::orientationHistogram(split, 15, y0, 155, y1);
  const auto right = dtf::test::orientationHistogram(split, 185, y0, 325, y1);
  const auto pl = dtf::test::peaks(left, 0.3), pr = dtf::test::peaks(right, 0.5);
  std::string list;
  for (double x : pl)
    list += std::to_string(x) + " ";
  list += "| ";
  for (double x : pr)
    list += std::to_string(x) + " ";
  EXPECT_LE(dtf::test::nearestPeak(pl, 30.0), 6.0) << "peaks left | right: " << list; // 3 bins
  EXPECT_LE(dtf::test::nearestPeak(pl, -30.0), 6.0) << "peaks left | right: " << list;
  EXPECT_LT(dtf::test::nearestPeak(pr, 0.0), 6.0) << "peaks left | right: " << list;
  EXPECT_LT(dtf::test::binValue(right, 30.0), 0.5) << "peaks left | right: " << list;
}
