// SPDX-License-Identifier: GPL-3.0-or-later
// Baseline image comparison shared by the baseline tests: a per-channel tolerance, a bad-pixel fraction
// and a mean difference. On failure the actual, expected and diff images go to
// build/baseline_failures/; DTF_UPDATE_BASELINES=1 rewrites the baseline instead (on purpose only, and
// look at the images before committing them).
#pragma once

#include "support/test_env.h"

#include "io/model/image.h"
#include "io/formats/png_io.h"
#include "render/gl_context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dtf::test {

inline constexpr int kChannelTolerance = 8;     // 0..255
inline constexpr double kMaxBadFraction = 0.01; // pixels with any channel beyond the tolerance
// The baselines are llvmpipe images. A hardware GPU filters textures with fixed-point weights, which moves
// a few percent of the thread pixels of the fabric's noise (1-2.4 % on an NVIDIA H200, mean difference
// below 0.5); the mean difference still bounds the whole image.
inline constexpr double kMaxBadFractionHardware = 0.05;
inline constexpr double kMaxMeanDiff = 1.5;     // mean |difference| over all channels


// Compares `actual` with tests/baseline/images/NAME.png (a GL context is current).
inline void compareToBaseline(const std::string& name, const Image& actual) {
  const std::filesystem::path expectedPath = sourceDir() / "tests/baseline/images" / (name + ".png");
  if (envFlag("DTF_UPDATE_BASELINES")) {
    io::writePng(expectedPath.string(), actual);
    std::printf("updated baseline %s\n", expectedPath.c_str());
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(expectedPath)) << "no baseline " << expectedPath << " (DTF_UPDATE_BASELINES=1 creates it)";
  Image expected = io::readPng(expectedPath.string());
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  Image diff(actual.width, actual.height);
  std::size_t bad = 0;
  double sum = 0;
  for (std::size_t i = 0; i < actual.rgba.size(); i += 4) {
    int worst = 0;
    for (int c = 0; c < 4; ++c) {
      int d = std::abs(int(actual.rgba[i + c]) - int(expected.rgba[i + c]));
      worst = std::max(worst, d);
      sum += d;
      if (c < 3) diff.rgba[i + c] = static_cast<std::uint8_t>(std::min(255, d * 8));
    }
    diff.rgba[i + 3] = 255;
    bad += worst > kChannelTolerance;
  }
  const double pixels = double(actual.width) * actual.height;
  const double badFraction = bad / pixels, meanDiff = sum / (pixels * 4);
  const double maxBad = render::softwareRasteriser() ? kMaxBadFraction : kMaxBadFractionHardware;
  if (badFraction > maxBad || meanDiff > kMaxMeanDiff) {
    const std::filesystem::path dir = binaryDir() / "baseline_failures";
    std::filesystem::create_directories(dir);
    io::writePng((dir / (name + "_actual.png")).string(), actual);
    io::writePng((dir / (name + "_expected.png")).string(), expected);
    io::writePng((dir / (name + "_diff.png")).string(), diff);
    ADD_FAILURE() << name << ": " << 100 * badFraction << "% bad pixels, mean difference " << meanDiff
                  << "; images in " << dir;
  }
}

} // namespace dtf::test
