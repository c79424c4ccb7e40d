// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view` under Xvfb with the tract colouring script commands: the AFQ .trx's arcuate bundles shown
// by group (ARC_L alone draws less than both) and the dpsv.trx tracts coloured by their per-point 'z'
// through the colour map instead of DEC, on the real iu_prisma brain; the whole window is kept for a look
// (Tracts panel: colour-by combo, range, colour bar, group checkboxes).
#include "io/formats/png_io.h"
#include "support/cli.h"
#include "support/test_env.h"
#include "support/window.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

namespace fs = std::filesystem;
using dtf::Image;

namespace {

// Share of the tract pixels of `img` (differing from `plain`) whose chromaticity (colour / its sum, as
// lighting scales the colour) lies within 0.12 (L1) of one of 64 samples of the colour map (viridis). The
// right fifth, where the colour bar's panel is drawn, is left out: only tracts are measured.
double shareNearColourMap(const Image& img, const Image& plain) {
  std::size_t tract = 0, near = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width * 4 / 5; ++x) {
      const auto *p = img.pixel(x, y), *q = plain.pixel(x, y);
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) < 60) continue;
      ++tract;
      const double s = p[0] + p[1] + p[2] + 1e-9;
      bool hit = false;
      for (int k = 0; k < 64 && !hit; ++k) {
        static const double map[5][3] = {{0x44, 0x01, 0x54},
                                         {0x3b, 0x52, 0x8b},
                                         {0x21, 0x91, 0x8c},
                                         {0x5e, 0xc9, 0x62},
                                         {0xfd, 0xe7, 0x25}};
        const double t = 4.0 * k / 63.0;
        const int i = std::min(3, int(t));
        const double f = t - i;
        double c[3], cs = 0;
        for (int j = 0; j < 3; ++j)
          cs += c[j] = map[i][j] * (1 - f) + map[i + 1][j] * f;
        double d = 0;
        for (int j = 0; j < 3; ++j)
          d += std::abs(p[j] / s - c[j] / cs);
        hit = d < 0.12;
      }
      near += hit;
    }
  return tract ? double(near) / double(tract) : 0;
}

} // namespace

TEST(ViewTractColouringWindow, GroupsAndValueColoursFromAScript) {
  DTF_XVFB_SETUP();
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(afq, "niivue_tracts/afq_tractography.trx");
  DTF_SHARED_FILE(dpsv, "niivue_tracts/dpsv.trx");
  const auto dir = dtf::test::scratchDir();
  auto shot = [&](const char* name) { return (dir / name).string(); };
  const auto r = dtf::test::runViewerScript(
      dir,
      "resize 1000x1000\nslice axial 8\ntracts-near 0\nscreenshot-scene " + shot("plain.png") + "\ntracts " +
          afq.string() + "\nscreenshot-scene " + shot("afq_all.png") +
          "\ntracts-groups ARC_L\nscreenshot-scene " + shot("afq_left.png") + "\ntracts-groups all\ntracts " +
          dpsv.string() + "\nscreenshot-scene " + shot("dpsv_dec.png") +
          "\ntracts-color z\nscreenshot-scene " + shot("dpsv_z.png") + "\nscreenshot " + shot("window.png") +
          "\nquit\n",
      "'" + tensor.string() + "'");
  DTF_SKIP_WITHOUT_WINDOW_GL(r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("tracts shown: 508 streamline pieces"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tracts shown: 486 streamline pieces"), std::string::npos) << "ARC_L alone\n" << r.err;
  EXPECT_NE(r.err.find("tracts coloured by 'z' from"), std::string::npos) << r.err;

  const Image plain = dtf::io::readPng(shot("plain.png"));
  const std::size_t all = dtf::test::tractPixels(dtf::io::readPng(shot("afq_all.png")), plain);
  const std::size_t left = dtf::test::tractPixels(dtf::io::readPng(shot("afq_left.png")), plain);
  EXPECT_GT(all, 2000u) << "both arcuate bundles drawn";
  EXPECT_GT(left, 1000u) << "ARC_L drawn";
  EXPECT_LT(left, all) << "hiding ARC_R removes pixels";

  const Image dec = dtf::io::readPng(shot("dpsv_dec.png")), byZ = dtf::io::readPng(shot("dpsv_z.png"));
  ASSERT_GT(dtf::test::tractPixels(dec, plain), 1000u);
  const double tractShare = double(dtf::test::tractPixels(dec, plain)) / double(dec.width * dec.height);
  EXPECT_GT(dtf::test::differingFraction(dec, byZ), 0.5 * tractShare)
      << "colouring by z changed the colours of most drawn tract pixels";
  const double decShare = shareNearColourMap(dec, plain), zShare = shareNearColourMap(byZ, plain);
  EXPECT_GT(zShare, 0.6) << "tracts take the colour map's colours";
  EXPECT_GT(zShare, decShare + 0.2) << "DEC " << decShare << ", by z " << zShare;
  std::printf("tract pixels near the colour map: DEC %.2f, by z %.2f\n", decShare, zShare);
}
