// SPDX-License-Identifier: GPL-3.0-or-later
// Baseline images of the tract overlay, rendered by the real `dtfabric render`: the real brain's axial
// slice 22 with its deterministic tractogram overlaid (tracts within 3 mm of the slice), and the
// `--split tracts` view of the same (two 256x256 panes: 512x256). Compared exactly like
// tests/render/baseline_test.cpp (same tolerances); regenerate on purpose only (DTF_UPDATE_BASELINES=1) and
// look at the images before committing them.
#include "support/baseline.h"
#include "support/gl_test.h"

#include "io/formats/png_io.h"

#include <cstdlib>
#include <filesystem>
#include <sys/wait.h>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

class TractBaseline : public GlTest {};


// Runs `dtfabric render ARGS -o OUT` and returns the PNG.
Image renderCli(const std::string& args, const fs::path& out) {
  // The paper's look without the figure furniture: the overlay is what these baselines hold.
  const std::string cmd = std::string(DTF_EXE) + " render " + args +
                          " --look plain --no-letters --no-legend --no-scale-bar -o " + out.string() + " --force";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;
  return fs::exists(out) ? io::readPng(out.string()) : Image();
}

// Pixels that are strongly DEC coloured (one channel far above the others): the tracts, mostly.
std::size_t saturated(const Image& img) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4) {
    const int r = img.rgba[i], g = img.rgba[i + 1], b = img.rgba[i + 2];
    n += std::max({r, g, b}) > 150 && std::min({r, g, b}) < 40;
  }
  return n;
}

} // namespace

TEST_F(TractBaseline, RealBrainAxialSliceWithTracts) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tracts, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = test::scratchDir();
  const std::string common =
      tensor.string() + " --surface slice=axial:22 --size 256x256 --tracts " + tracts.string();
  Image img = renderCli(common, dir / "overlay.png");
  ASSERT_EQ(img.width, 256);
  ASSERT_EQ(img.height, 256);
  Image plain = renderCli(tensor.string() + " --surface slice=axial:22 --size 256x256", dir / "plain.png");
  ASSERT_EQ(plain.width, 256);
  // The overlay adds saturated tract pixels to the fabric.
  EXPECT_GT(saturated(img), saturated(plain) + 500);
  test::compareToBaseline("brain_axial22_tracts", img);
}

TEST_F(TractBaseline, RealBrainSplitFabricAndTracts) {
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(tracts, "iu_prisma_dwi/derived/tracks_det.tck");
  const fs::path dir = test::scratchDir();
  Image img = renderCli(tensor.string() + " --surface slice=axial:22 --size 256x256 --tracts " +
                            tracts.string() + " --split tracts",
                        dir / "split.png");
  ASSERT_EQ(img.width, 512);
  ASSERT_EQ(img.height, 256);
  // Left pane: the fabric alone; right pane: the same fabric with the tracts.
  Image left(256, 256), right(256, 256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      for (int c = 0; c < 4; ++c) {
        left.pixel(x, y)[c] = img.pixel(x, y)[c];
        right.pixel(x, y)[c] = img.pixel(x + 256, y)[c];
      }
  EXPECT_GT(saturated(right), saturated(left) + 500);
  test::compareToBaseline("brain_axial22_split_tracts", img);
}
