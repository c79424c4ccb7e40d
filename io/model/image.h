// SPDX-License-Identifier: GPL-3.0-or-later
// 8-bit RGBA images, row 0 at the top. The product of a render, the input of PNG writing and baseline
// comparison.
#pragma once

#include <cstdint>
#include <vector>

namespace dtf {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba; // width * height * 4

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0) {}
  std::uint8_t* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

// `left` and `right` (same height) side by side: width left.width + right.width (two linked panes in one
// image). Throws Error for different heights.
Image sideBySide(const Image& left, const Image& right);

} // namespace dtf
