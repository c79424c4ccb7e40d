// SPDX-License-Identifier: GPL-3.0-or-later
// Hardening of `dtfabric view` in a real window under Xvfb: a malformed file and a field beyond the GL's 3D
// texture limit open the error modal while the viewer goes on (a good file loads afterwards); a script's
// screenshot and camera-save lines do not replace files they did not write unless they say --force.
// Skips without xvfb-run unless DTF_REQUIRE_GL=1.
#include "io/formats/png_io.h"
#include "io/formats/tensor_io.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <cstdlib>
#include <fstream>
#include <gtest/gtest.h>

namespace fs = std::filesystem;
using dtf::Image;

namespace {

const fs::path kSample = dtf::test::sourceDir() / "sample_data" / "brain_phantom.nii.gz";

dtf::test::CliResult runViewer(const fs::path& scratch, const std::string& script,
                               const std::string& args = "") {
  return dtf::test::runViewerScript(scratch, script, args);
}

// Pixels of the rectangle [x0, x1) x [y0, y1) within `tol` of an RGB colour.
std::size_t countColour(const Image& img, int x0, int y0, int x1, int y1, int r, int g, int b, int tol) {
  std::size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto* p = img.pixel(x, y);
      n += std::abs(p[0] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[2] - b) <= tol;
    }
  return n;
}

double litFraction(const Image& img) {
  std::size_t n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto* p = img.pixel(x, y);
      n += p[0] + p[1] + p[2] > 60;
    }
  return double(n) / (double(img.width) * img.height);
}

// The error modal's title bar: Dear ImGui's dark style TitleBgActive (0.16, 0.29, 0.48), in the middle of
// the window, where nothing else has that colour (the panels' headers are lighter blue, the scene is dark
// without data).
std::size_t modalTitlePixels(const Image& win) {
  return countColour(win, 170, 140, 470, 340, 41, 74, 122, 6);
}

} // namespace

TEST(ViewHardening, MalformedFileOpensTheErrorModalAndTheViewerGoesOn) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const fs::path bad = dir / "bad.nii";
  std::ofstream(bad) << std::string(400, 'x'); // no NIfTI header
  const auto r =
      runViewer(dir, "screenshot " + (dir / "before.png").string() + "\nload " + bad.string() +
                         "\nscreenshot " + (dir / "modal.png").string() + "\nload " + kSample.string() +
                         "\nscreenshot-scene " + (dir / "after.png").string() + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  // The message names the script line, the file and the problem; nifticlib adds nothing of its own.
  EXPECT_NE(r.err.find("script.txt:2: error: while loading " + bad.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(bad.string() + ": bad sizeof_hdr"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("** ERROR"), std::string::npos) << r.err;
  const Image before = dtf::io::readPng((dir / "before.png").string());
  const Image modal = dtf::io::readPng((dir / "modal.png").string());
  EXPECT_EQ(modalTitlePixels(before), 0u);
  EXPECT_GT(modalTitlePixels(modal), 1000u) << "no error modal in the middle of the window";
  // The viewer went on: the next load put the fabric on screen.
  const Image after = dtf::io::readPng((dir / "after.png").string());
  EXPECT_GT(litFraction(after), 0.05);
}

TEST(ViewHardening, FieldBeyondThe3DTextureLimitIsAGlErrorInTheModal) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  // 32767 voxels (the largest NIfTI-1 axis) along x: beyond GL_MAX_3D_TEXTURE_SIZE of llvmpipe (2048) and of
  // every GPU driver we know (at most 16384), yet only 3 MiB of tensors.
  dtf::TensorField f = dtf::makeTensorField(dtf::Grid::fromAffine({32767, 2, 2}, glm::dmat4(1.0)));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    f.tensors[i] = dtf::SymTensor{1.7e-3f, 0, 0, 0.3e-3f, 0, 0.3e-3f};
    f.valid[i] = 1;
  }
  const fs::path wide = dir / "wide.nii";
  dtf::io::writeTensorVolume(wide.string(), f, dtf::io::TensorLayout::Mrtrix);
  const auto r = runViewer(dir, "surface slice=axial\nload " + wide.string() + "\nwait 5\nscreenshot " +
                                    (dir / "modal.png").string() + "\nload " + kSample.string() +
                                    "\nscreenshot-scene " + (dir / "after.png").string() + "\nquit\n");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  EXPECT_EQ(r.exitCode, 3) << r.err; // the script's failure was GL's
  EXPECT_NE(r.err.find("32767x2x2 exceeds this GL's 3D texture size limit"), std::string::npos) << r.err;
  EXPECT_GT(modalTitlePixels(dtf::io::readPng((dir / "modal.png").string())), 1000u);
  EXPECT_GT(litFraction(dtf::io::readPng((dir / "after.png").string())), 0.05);
}

TEST(ViewHardening, ScriptOutputsDoNotReplaceFilesWithoutForce) {
  DTF_XVFB_SETUP();
  const auto dir = dtf::test::scratchDir();
  const std::string shot = (dir / "shot.png").string(), first = (dir / "first.png").string();
  const std::string cam = (dir / "view.camera").string();
  // Both outputs are new when the script starts; the second write of each finds the first.
  const std::string script = "fa 0.25\nscreenshot-scene " + shot + "\nscreenshot-scene " + first +
                             "\ncamera-save " + cam + "\nrotate 90 0\nscreenshot-scene " + shot +
                             "\ncamera-save " + cam + "\nquit\n";
  const auto r = runViewer(dir, script, "'" + kSample.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("script.txt:6: error: " + shot + " exists (use --force"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("script.txt:7: error: " + cam + " exists (use --force"), std::string::npos) << r.err;
  // shot.png is still the first view, not the rotated one.
  EXPECT_LT(dtf::test::differingFraction(dtf::io::readPng(shot), dtf::io::readPng(first)), 0.001);
  const std::string camBefore = dtf::test::readText(cam);

  // --force on the lines replaces them (`view --force`, the same for every line, is checked in
  // malformed_inputs_test.cpp).
  fs::remove(shot);
  fs::remove(first);
  fs::remove(cam);
  std::string forced = script;
  forced.replace(forced.rfind("camera-save "), 12, "camera-save --force ");
  forced.replace(forced.rfind("screenshot-scene "), 17, "screenshot-scene --force ");
  const auto f = runViewer(dir, forced, "'" + kSample.string() + "'");
  EXPECT_EQ(f.exitCode, 0) << f.err;
  EXPECT_GT(dtf::test::differingFraction(dtf::io::readPng(shot), dtf::io::readPng(first)), 0.02)
      << "the rotated view did not replace the first screenshot";
  EXPECT_NE(dtf::test::readText(cam), camBefore) << "the rotated camera did not replace the first";
}
