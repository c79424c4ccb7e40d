// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view --ortho` in a real window under Xvfb, driven by a script: the crosshair and click lines move
// the crosshair (printed with its slices), the scene screenshot exports the whole layout at the scene's size,
// and `movie turntable` records the 3D pane to PNG frames and an MP4 with the frame count asked for.
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <gtest/gtest.h>
#include <regex>

namespace fs = std::filesystem;

namespace {

const fs::path kSample = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

struct Crosshair {
  double x = 0, y = 0, z = 0;
  int axial = -1, coronal = -1, sagittal = -1;
};

// The crosshair lines a script printed, in order.
std::vector<Crosshair> crosshairs(const std::string& err) {
  std::vector<Crosshair> out;
  const std::regex re(R"(crosshair (-?[0-9.]+) (-?[0-9.]+) (-?[0-9.]+) mm, slices axial (\d+) coronal (\d+) sagittal (\d+))");
  for (std::sregex_iterator it(err.begin(), err.end(), re), end; it != end; ++it)
    out.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]), std::stoi((*it)[4]),
                   std::stoi((*it)[5]), std::stoi((*it)[6])});
  return out;
}

} // namespace

TEST(OrthoWindow, CrosshairClickLayoutExportAndTurntable) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  // Scene 340x454: the axial pane is the top-left 170x227; its centre shows the crosshair at the data centre.
  const std::string script = "crosshair 0 0 0\n"
                             "screenshot-scene " + (dir / "layout1.png").string() + "\n"
                             "click 60 60\n"
                             "screenshot-scene " + (dir / "layout2.png").string() + "\n"
                             "movie turntable 6 " + (dir / "frames").string() + "/\n"
                             "movie turntable 5 " + (dir / "turn.mp4").string() + "\n"
                             "quit\n";
  const auto r = dtf::test::runViewerScript(dir, script, "--ortho '" + kSample.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto c = crosshairs(r.err);
  ASSERT_EQ(c.size(), 2u) << r.err;
  EXPECT_NEAR(c[0].x, 0, 0.01);
  EXPECT_EQ(c[0].axial, 24);
  // The click lies up and to the left of the centre in the axial pane: anterior, the patient's right.
  EXPECT_GT(c[1].x, 5);
  EXPECT_GT(c[1].y, 5);
  EXPECT_NEAR(c[1].z, 0, 0.01);
  EXPECT_EQ(c[1].axial, c[0].axial);
  EXPECT_GT(c[1].coronal, c[0].coronal);
  EXPECT_GT(c[1].sagittal, c[0].sagittal);

  const dtf::Image a = dtf::io::readPng((dir / "layout1.png").string());
  const dtf::Image b = dtf::io::readPng((dir / "layout2.png").string());
  EXPECT_EQ(a.width, 340);
  EXPECT_EQ(a.height, 454);
  EXPECT_EQ(b.width, 340);
  EXPECT_EQ(b.height, 454);
  // The coronal and sagittal panes changed with the click; the pane borders are drawn.
  EXPECT_GT(dtf::test::differingFraction(a, b), 0.01);
  EXPECT_EQ(a.pixel(169, 300)[0], 90);

  std::size_t frames = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames")) frames += e.path().extension() == ".png";
  EXPECT_EQ(frames, 6u);
  const dtf::Image f0 = dtf::io::readPng((dir / "frames" / "frame_0000.png").string());
  EXPECT_EQ(f0.width, 170); // the 3D pane
  EXPECT_EQ(f0.height, 227);
  if (std::system("command -v ffprobe > /dev/null") == 0) {
    const fs::path probe = dir / "probe.txt";
    const std::string cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                            "stream=nb_read_frames,width,height -of csv=p=0 '" +
                            (dir / "turn.mp4").string() + "' > '" + probe.string() + "'";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_EQ(dtf::test::readText(probe), "170,226,5\n"); // H.264: even sizes
  } else if (dtf::test::envFlag("DTF_REQUIRE_GL")) {
    FAIL() << "ffprobe missing (.ci/setup installs ffmpeg)";
  }
}
