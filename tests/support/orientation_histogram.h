// SPDX-License-Identifier: GPL-3.0-or-later
// Orientation histograms of rendered fabric images: the checks the fibre renders and the viewer's fibre
// mode share (the threads of each bundle make a peak at its direction, the tensor average none).
#pragma once

#include "io/model/image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace dtf::test {

constexpr int kBins = 90; // 2 degrees each

// Histogram of local line orientations (degrees in [0, 180), counter-clockwise from image +x, y up) inside
// the window: per pixel the Sobel gradient of the luminance, its line direction (perpendicular to the
// gradient) weighted by the squared gradient magnitude. No window averaging (a structure tensor summed over
// a window would itself average two crossing orientations into their bisector). Circularly smoothed over
// +-2 bins and normalised to a maximum of 1.
inline std::array<double, kBins> orientationHistogram(const Image& img, int x0, int y0, int x1, int y1) {
  auto lum = [&](int x, int y) {
    const auto* p = img.pixel(x, y);
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  };
  std::array<double, kBins> hist{};
  for (int y = y0 + 1; y < y1 - 1; ++y)
    for (int x = x0 + 1; x < x1 - 1; ++x) {
      const double gx = (lum(x + 1, y - 1) + 2 * lum(x + 1, y) + lum(x + 1, y + 1)) -
                        (lum(x - 1, y - 1) + 2 * lum(x - 1, y) + lum(x - 1, y + 1));
      const double gy = -((lum(x - 1, y + 1) + 2 * lum(x, y + 1) + lum(x + 1, y + 1)) -
                          (lum(x - 1, y - 1) + 2 * lum(x, y - 1) + lum(x + 1, y - 1))); // y up
      double deg = std::atan2(gy, gx) * 180.0 / M_PI + 90.0;
      deg = std::fmod(deg + 360.0, 180.0);
      hist[static_cast<std::size_t>(deg / 2.0) % kBins] += gx * gx + gy * gy;
    }
  std::array<double, kBins> smooth{};
  double top = 0;
  for (int b = 0; b < kBins; ++b) {
    for (int d = -2; d <= 2; ++d)
      smooth[static_cast<std::size_t>(b)] += hist[static_cast<std::size_t>((b + d + kBins) % kBins)];
    top = std::max(top, smooth[static_cast<std::size_t>(b)]);
  }
  for (double& v : smooth)
    v /= top;
  return smooth;
}

inline double binValue(const std::array<double, kBins>& h, double deg) {
  return h[static_cast<std::size_t>(std::fmod(deg + 360.0, 180.0) / 2.0) % kBins];
}

// Local maxima of the histogram above `floor`, as orientations in degrees (bin centres).
inline std::vector<double> peaks(const std::array<double, kBins>& h, double floor) {
  std::vector<double> out;
  for (int b = 0; b < kBins; ++b) {
    const double v = h[static_cast<std::size_t>(b)];
    if (v >= floor && v >= h[static_cast<std::size_t>((b + 1) % kBins)] &&
        v > h[static_cast<std::size_t>((b + kBins - 1) % kBins)])
      out.push_back(2.0 * b + 1.0);
  }
  return out;
}

// Smallest difference of two orientations (mod 180), degrees.
inline double orientationDiff(double a, double b) {
  double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180.0 - d);
}

inline double nearestPeak(const std::vector<double>& p, double deg) {
  double best = 180;
  for (double x : p)
    best = std::min(best, orientationDiff(x, deg));
  return best;
}

} // namespace dtf::test
