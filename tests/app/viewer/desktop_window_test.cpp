// SPDX-License-Identifier: GPL-3.0-or-later
// The viewer as a desktop application, in a real GLFW window under Xvfb (no desktop portal there): the file
// dialog's fallback, the in-window browser, lists a folder and opens a file as a typed path opens it; a drop
// of a volume, a tractogram and a mesh opens each as its kind; a bad drop opens nothing; a saved session
// replays to the same scene; a session naming a missing file fails before a window opens; --ui-scale 2 draws
// the side bar twice as wide with text rasterised at that size (sharper than the scale-1 panels magnified);
// F1 shows the bindings. The screenshots of the browser, a restored session and scale 2 are kept in the
// test's scratch folder to look at.
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>

namespace fs = std::filesystem;
using dtf::Image;

namespace {

const fs::path kPhantom = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The lines of `text` that start with `prefix`.
std::vector<std::string> linesStarting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// Mean absolute difference per channel over the two images (same size).
double meanAbsDifference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return 255;
  double sum = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      sum += std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c]));
  return sum / double(a.rgba.size() / 4 * 3);
}

// ImGui's dark style's collapsing header (Header (0.26, 0.59, 0.98) at alpha 0.31 over the window's grey).
bool headerBlue(const Image& img, int x, int y) {
  const auto* p = img.pixel(x, y);
  return std::abs(p[0] - 30) < 6 && std::abs(p[1] - 56) < 6 && std::abs(p[2] - 87) < 6;
}

// The right edge of the side bar's collapsing headers: along each row of the top third whose pixel at x0
// (right of the header's arrow and title) is ImGui's header blue, the last blue column of the unbroken run
// from x0; the largest over those rows. The scene (whose fabric may be blue) is never reached.
int headerRightEdge(const Image& img, int x0) {
  int right = -1;
  for (int y = 0; y < img.height / 3; ++y) {
    if (!headerBlue(img, x0, y)) continue;
    int x = x0;
    while (x + 1 < img.width && headerBlue(img, x + 1, y))
      ++x;
    right = std::max(right, x);
  }
  return right;
}

float luma(const Image& img, int x, int y) {
  const auto* p = img.pixel(x, y);
  return 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
}

// How sharp the text in the columns [0, w) is: of the horizontal neighbour steps in brightness above 24
// (edges), the share above 96 (a glyph edge within one pixel rather than spread over two).
double edgeSharpness(const Image& img, int w) {
  std::size_t edges = 0, sharp = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 1; x < w; ++x) {
      const float d = std::abs(luma(img, x, y) - luma(img, x - 1, y));
      if (d > 24) ++edges;
      if (d > 96) ++sharp;
    }
  return edges ? double(sharp) / double(edges) : 0;
}

// `img` magnified twice with bilinear interpolation (pixel centres), as a scale-1 UI stretched to scale 2
// would look.
Image magnified(const Image& img) {
  Image out(img.width * 2, img.height * 2);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const double sx = std::clamp((x + 0.5) / 2 - 0.5, 0.0, img.width - 1.0);
      const double sy = std::clamp((y + 0.5) / 2 - 0.5, 0.0, img.height - 1.0);
      const int x0 = int(sx), y0 = int(sy), x1 = std::min(x0 + 1, img.width - 1),
                y1 = std::min(y0 + 1, img.height - 1);
      const double fx = sx - x0, fy = sy - y0;
      for (int c = 0; c < 4; ++c) {
        const double v = (1 - fy) * ((1 - fx) * img.pixel(x0, y0)[c] + fx * img.pixel(x1, y0)[c]) +
                         fy * ((1 - fx) * img.pixel(x0, y1)[c] + fx * img.pixel(x1, y1)[c]);
        out.rgba[(std::size_t(y) * out.width + x) * 4 + c] = static_cast<std::uint8_t>(std::lround(v));
      }
    }
  return out;
}

} // namespace

// The Data panel's dialog under Xvfb (no portal): the in-window browser lists the folder, and picking the
// phantom there opens it as the Data panel opens a typed path (the probe finds its voxels afterwards).
TEST(DesktopWindow, BrowserFallbackListsAFolderAndOpensTheChosenFile) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  fs::create_directories(dir / "data" / "sub-01");
  fs::copy_file(kPhantom, dir / "data" / "brain_phantom.nii.gz");
  std::ofstream(dir / "data" / "notes.txt") << "not a volume";
  const auto r = dtf::test::runViewerScript(
      dir,
      "browse data " + (dir / "data").string() + "\nwait 2\nscreenshot " + (dir / "browser.png").string() +
          "\nbrowser-pick brain_phantom.nii.gz\nkey A\nprobe 170 227\nscreenshot " +
          (dir / "opened.png").string() + "\nquit\n",
      "");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Opened: the probe at the scene's centre lands on the phantom's middle axial slice.
  EXPECT_TRUE(has(r.err, "probe 170 227: surface at")) << r.err;
  EXPECT_TRUE(has(r.err, "voxel ")) << r.err;
  // The browser was drawn over the panels: the window differs from the one with the data open, and its
  // modal darkens the side bar.
  const Image browser = dtf::io::readPng((dir / "browser.png").string());
  const Image opened = dtf::io::readPng((dir / "opened.png").string());
  EXPECT_GT(dtf::test::differingFraction(browser, opened), 0.2);
}

// A drop of three files of different kinds (the real brain's tensors, its first 500 streamlines as legacy
// VTK lines, a mesh written by `dtfabric surface`): each opens as its kind, which the saved session shows.
TEST(DesktopWindow, ADropOfThreeKindsOpensEachAsItsKind) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensorIn, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(vtkIn, "iu_prisma_dwi/derived/tracks_det_first500.vtk");
  // A drop names files by their absolute, normalised paths.
  const fs::path tensor = fs::absolute(tensorIn).lexically_normal(),
                 vtk = fs::absolute(vtkIn).lexically_normal();
  const auto dir = dtf::test::scratchDir();
  const fs::path mesh = dir / "fa35.ply";
  const auto made = dtf::test::runDtfabric(
      "surface '" + tensor.string() + "' --surface fa=0.35 --output '" + mesh.string() + "'", dir);
  ASSERT_EQ(made.exitCode, 0) << made.err;
  const fs::path saved = dir / "after_drop.dtfview";
  const auto r =
      dtf::test::runViewerScript(dir,
                                 "drop '" + vtk.string() + "' '" + tensor.string() + "' '" + mesh.string() +
                                     "'\nwait 2\nscreenshot-scene " + (dir / "dropped.png").string() +
                                     "\nsession-save " + saved.string() + "\nquit\n",
                                 "");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(has(r.err, "drop: " + tensor.string() + " opens as data")) << r.err;
  EXPECT_TRUE(has(r.err, "drop: " + vtk.string() + " opens as tracts")) << r.err;
  EXPECT_TRUE(has(r.err, "drop: " + mesh.string() + " opens as the surface")) << r.err;
  EXPECT_TRUE(has(r.err, vtk.string() + ": 500 streamlines")) << r.err;
  const std::string session = readFile(saved);
  EXPECT_TRUE(has(session, "\nload " + tensor.string() + "\n")) << session;
  EXPECT_TRUE(has(session, "\nsurface mesh=" + mesh.string() + "\n")) << session;
  EXPECT_TRUE(has(session, "\ntracts " + vtk.string() + "\n")) << session;
}

// A drop naming a missing file next to a good one: the error names the missing file, and nothing of the drop
// opens (the scene and the session are those from before it).
TEST(DesktopWindow, ABadDropFailsClearlyAndChangesNothing) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const fs::path missing = dir / "missing_dwi.nii.gz";
  const auto r = dtf::test::runViewerScript(
      dir,
      "set look plain\nkey A\nscreenshot-scene " + (dir / "before.png").string() + "\nsession-save " +
          (dir / "before.dtfview").string() + "\ndrop " + tck.string() + " " + missing.string() +
          "\nwait 2\nscreenshot-scene " + (dir / "after.png").string() + "\nsession-save " +
          (dir / "after.dtfview").string() + "\nquit\n",
      "'" + kPhantom.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_TRUE(has(r.err, "script.txt:5: error: while opening the dropped files: " + missing.string() +
                             ": no such file"))
      << r.err;
  EXPECT_FALSE(has(r.err, "opens as")) << "nothing of the drop opened\n" << r.err;
  EXPECT_EQ(readFile(dir / "before.dtfview"), readFile(dir / "after.dtfview"));
  const Image before = dtf::io::readPng((dir / "before.png").string());
  const Image after = dtf::io::readPng((dir / "after.png").string());
  EXPECT_LT(meanAbsDifference(before, after), 0.5);
}

// A view set up by several changes (slice, camera turned, zoomed and panned, split with Phong on the right,
// a fabric option, the background, the furniture, tracts coloured and clipped) saved as a session, then
// replayed by `view --script SESSION` alone: the same scene to within rounding.
TEST(DesktopWindow, ASavedSessionReplaysToTheSameScene) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tck, "iu_prisma_dwi/derived/tracks_det.tck");
  const auto dir = dtf::test::scratchDir();
  const fs::path session = dir / "figure.dtfview";
  const auto first = dtf::test::runViewerScript(
      dir,
      "key C\nslice coronal 40\nrotate 70 -30\nzoom 1.3\npan 12 -8\nsplit phong\nset blend-k 0.15\n"
      "background fa\nfurniture scale-bar off\ntracts " +
          tck.string() + "\ntracts-near 4\ntract-width 3\nscreenshot-scene " +
          (dir / "original.png").string() + "\nsession-save " + session.string() + "\nquit\n",
      "'" + tensor.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(first);
  ASSERT_EQ(first.exitCode, 0) << first.err;
  const std::string text = readFile(session);
  EXPECT_TRUE(text.rfind("# dtfabric viewer session", 0) == 0) << text;
  EXPECT_TRUE(has(text, "\nsession 1\nresize 640x480\n")) << text;
  EXPECT_TRUE(has(text, "\nsurface slice=coronal:40\n")) << text;
  EXPECT_TRUE(has(text, "\nset blend-k 0.15")) << text;
  EXPECT_TRUE(has(text, "\nsplit phong\n")) << text;
  EXPECT_TRUE(has(text, "\ntract-width 3\n")) << text;
  EXPECT_TRUE(linesStarting(text, "rotate").empty() && linesStarting(text, "zoom").empty())
      << "state, not history";
  EXPECT_EQ(linesStarting(text, "camera ").size(), 1u) << text;

  // The replay: the session alone, then a screenshot of what it brought back.
  const fs::path replay = dir / "replay.dtfview";
  std::ofstream(replay) << text << "screenshot-scene " << (dir / "restored.png").string() << "\nscreenshot "
                        << (dir / "restored_window.png").string() << "\nquit\n";
  const fs::path replayDir = dir / "replay";
  fs::create_directories(replayDir);
  const auto second = dtf::test::runViewerScript(replayDir, readFile(replay), "");
  ASSERT_EQ(second.exitCode, 0) << second.err;
  const Image a = dtf::io::readPng((dir / "original.png").string());
  const Image b = dtf::io::readPng((dir / "restored.png").string());
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  const double mean = meanAbsDifference(a, b), differing = dtf::test::differingFraction(a, b);
  std::printf("session replay: mean |difference| %.3f per channel, %.4f%% of pixels differ by more than 40\n",
              mean, 100 * differing);
  EXPECT_LT(mean, 1.0);
  EXPECT_LT(differing, 0.002);
}

// A session naming a file that is gone fails before a window opens: exit code 2, the file and the line named,
// nothing written.
TEST(DesktopWindow, ASessionNamingAMissingFileFailsAndShowsNothing) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  std::ofstream(dir / "gone.dtfview")
      << "session 1\nresize 640x480\nload " << kPhantom.string() << "\ntracts " << (dir / "gone.tck").string()
      << "\nscreenshot " << (dir / "never.png").string() << "\nquit\n";
  const auto r = dtf::test::runDtfabric("view --script '" + (dir / "gone.dtfview").string() + "'", dir);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_TRUE(
      has(r.err, (dir / "gone.dtfview").string() + ":4: " + (dir / "gone.tck").string() + ": no such file"))
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "never.png"));
}

// --ui-scale 2: the side bar is twice as wide and its text is drawn from the font at twice the size, so its
// glyph edges stay as sharp as at scale 1 (a scale-1 window magnified twice has soft, two-pixel edges).
TEST(DesktopWindow, UiScale2DrawsPanelsTwiceAsWideWithSharpText) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const auto one = dtf::test::runViewerScript(
      dir, "resize 640x480\nscreenshot " + (dir / "scale1.png").string() + "\nquit\n",
      "'" + kPhantom.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(one);
  ASSERT_EQ(one.exitCode, 0) << one.err;
  const fs::path dir2 = dir / "two";
  fs::create_directories(dir2);
  const auto two = dtf::test::runViewerScript(dir2,
                                              "resize 1280x960\nkey R\nscreenshot " +
                                                  (dir / "scale2.png").string() + "\nhelp on\nscreenshot " +
                                                  (dir / "scale2_help.png").string() + "\nquit\n",
                                              "'" + kPhantom.string() + "' --ui-scale 2");
  ASSERT_EQ(two.exitCode, 0) << two.err;
  const Image s1 = dtf::io::readPng((dir / "scale1.png").string());
  const Image s2 = dtf::io::readPng((dir / "scale2.png").string());
  ASSERT_EQ(s2.width, 1280);
  const int e1 = headerRightEdge(s1, 150), e2 = headerRightEdge(s2, 300);
  std::printf("side bar header edge: scale 1 at x = %d, scale 2 at x = %d\n", e1, e2);
  ASSERT_GT(e1, 200);
  EXPECT_NEAR(double(e2 + 1) / double(e1 + 1), 2.0, 0.06);
  // The status bar is twice as tall: the scene's height is the window's less 2 x 26 px.
  const double sharp2 = edgeSharpness(s2, e2), stretched = edgeSharpness(magnified(s1), 2 * e1);
  std::printf("text edges sharper than 96 levels: scale 2 %.3f, scale 1 magnified %.3f\n", sharp2, stretched);
  EXPECT_GT(sharp2, stretched + 0.1);
  // F1's help over the scene at scale 2.
  const Image help = dtf::io::readPng((dir / "scale2_help.png").string());
  EXPECT_GT(dtf::test::differingFraction(s2, help), 0.02);
}

// The remembered settings: a run without a script writes them when it closes (here by SIGTERM, which closes
// the window as its close button does), the next run starts from them, and a flag given wins over them.
TEST(DesktopWindow, SettingsAreRememberedBetweenRunsAndFlagsWin) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const fs::path config = dir / "config", conf = config / "dtfabric" / "viewer.conf";
  // Runs the viewer without a script for a few seconds under Xvfb, then closes it with SIGTERM.
  auto run = [&](const std::string& args, const std::string& name) {
    const fs::path err = dir / (name + ".txt");
    const std::string cmd = "XDG_CONFIG_HOME='" + config.string() +
                            "' timeout 120 xvfb-run -a -s '-screen 0 1280x1024x24' sh -c \"'" + DTF_EXE +
                            "' view '" + kPhantom.string() + "' " + args + " 2>'" + err.string() +
                            "' & pid=\\$!; sleep 6; kill -TERM \\$pid; wait \\$pid; echo rc=\\$? >>'" + err.string() +
                            "'\" >/dev/null 2>&1";
    std::system(cmd.c_str());
    return readFile(err);
  };
  const std::string first = run("--size 700x500 --ui-scale 1.5", "first");
  if (has(first, "GLFW") && !dtf::test::envFlag("DTF_REQUIRE_GL")) GTEST_SKIP() << "no GL window: " << first;
  EXPECT_TRUE(has(first, "settings: " + conf.string() + " (window 700x500, UI scale 1.50)")) << first;
  EXPECT_TRUE(has(first, "rc=143")) << "closed by SIGTERM\n" << first;
  const std::string text = readFile(conf);
  EXPECT_TRUE(has(text, "\nsize 700 500\n")) << text;
  EXPECT_TRUE(has(text, "\nui-scale 1.5\n")) << text;
  EXPECT_TRUE(has(text, "\nrecent-file " + kPhantom.string() + "\n")) << text;
  EXPECT_TRUE(has(text, "\npanel open Data\n")) << text;

  const std::string second = run("", "second");
  EXPECT_TRUE(has(second, "(window 700x500, UI scale 1.50)")) << "remembered\n" << second;
  const std::string third = run("--size 800x600", "third");
  EXPECT_TRUE(has(third, "(window 800x600, UI scale 1.50)")) << "--size wins\n" << third;
  // --no-config: neither read nor written.
  fs::remove(conf);
  const std::string clean = run("--no-config", "clean");
  EXPECT_FALSE(has(clean, "settings:")) << clean;
  EXPECT_FALSE(fs::exists(conf));
}
