// SPDX-License-Identifier: GPL-3.0-or-later
// Checks on the pictures the user guide and the demo show: made, decodable, not blank, and the colour
// and thread direction of a region.
#pragma once

#include "io/model/image.h"
#include "io/formats/png_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace dtf::test {

// What makes a picture blank or not: the share of pixels unlike the corner pixel (the background, or the
// window's title bar) and the spread of their brightness (a flat fill has none).
struct FigureContent {
  double foreground = 0;   // fraction of pixels whose RGB differs from the corner pixel's by more than 30
  double brightnessSd = 0; // standard deviation of the foreground's brightness, 0..255
  std::size_t colours = 0; // distinct RGB colours (quantised to 5 bits per channel) in the foreground
};

inline FigureContent figureContent(const Image& img) {
  FigureContent c;
  if (img.width <= 0 || img.height <= 0) return c;
  const std::uint8_t* bg = img.pixel(0, 0);
  std::size_t n = 0;
  double sum = 0, sum2 = 0;
  std::set<int> colours;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      if (std::abs(p[0] - bg[0]) + std::abs(p[1] - bg[1]) + std::abs(p[2] - bg[2]) <= 30) continue;
      ++n;
      const double l = (p[0] + p[1] + p[2]) / 3.0;
      sum += l;
      sum2 += l * l;
      colours.insert((p[0] >> 3) << 10 | (p[1] >> 3) << 5 | (p[2] >> 3));
    }
  const double total = double(img.width) * img.height;
  c.foreground = n / total;
  if (n > 1) c.brightnessSd = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  c.colours = colours.size();
  return c;
}

// Empty when the PNG at `path` exists, decodes and shows something (at least 5% foreground with a
// brightness spread and more than 50 colours); else what is wrong with it.
inline std::string figureProblem(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return path.string() + ": not made";
  Image img;
  try {
    img = io::readPng(path.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  const FigureContent c = figureContent(img);
  std::ostringstream why;
  if (c.foreground < 0.05 || c.brightnessSd < 10 || c.colours <= 50)
    why << path.string() << ": blank (foreground " << c.foreground << ", brightness sd " << c.brightnessSd
        << ", " << c.colours << " colours)";
  return why.str();
}

// Names of the PNGs under figures/ that a Markdown file links (`figures/NAME.png`, any prefix).
inline std::set<std::string> referencedFigures(const std::filesystem::path& markdown) {
  std::ifstream in(markdown);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  std::set<std::string> names;
  const std::regex link(R"(figures/([A-Za-z0-9_.-]+\.png))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1]);
  return names;
}

// Mean RGB over the box [x0, x1) x [y0, y1) given as fractions of the image size.
struct Rgb {
  double r = 0, g = 0, b = 0;
};
inline Rgb meanColour(const Image& img, double x0, double y0, double x1, double y1) {
  Rgb m;
  std::size_t n = 0;
  for (int y = int(y0 * img.height); y < int(y1 * img.height); ++y)
    for (int x = int(x0 * img.width); x < int(x1 * img.width); ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      m.r += p[0];
      m.g += p[1];
      m.b += p[2];
      ++n;
    }
  if (n) m = {m.r / n, m.g / n, m.b / n};
  return m;
}

// Summed |brightness difference| to the right neighbour over that to the lower neighbour in the box:
// below 1 where threads run left-right on the image (brightness changes across them, vertically).
inline double horizontalOverVerticalChange(const Image& img, double x0, double y0, double x1, double y1) {
  auto lum = [&](int x, int y) {
    const std::uint8_t* p = img.pixel(x, y);
    return (p[0] + p[1] + p[2]) / 3.0;
  };
  double dx = 0, dy = 0;
  for (int y = int(y0 * img.height); y < int(y1 * img.height) - 1; ++y)
    for (int x = int(x0 * img.width); x < int(x1 * img.width) - 1; ++x) {
      dx += std::abs(lum(x + 1, y) - lum(x, y));
      dy += std::abs(lum(x, y + 1) - lum(x, y));
    }
  return dy > 0 ? dx / dy : 1e9;
}

} // namespace dtf::test
