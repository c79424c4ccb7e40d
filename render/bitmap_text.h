// SPDX-License-Identifier: GPL-3.0-or-later
// A small built-in 5x7 bitmap font for labelling rendered images on the CPU (contact sheets, panel
// captions): no font files, no GL. Upper and lower case letters, digits and some punctuation; other characters
// draw as their capital, else as '?'.
#pragma once

#include "io/model/image.h"

#include <cstdint>
#include <string>

namespace dtf::render {

// Where labels and figure furniture are drawn: an image, or a host's 2D draw list (the viewer draws the same
// furniture over its panes). Everything is opaque rectangles, clipped to the canvas.
class Canvas {
public:
  virtual ~Canvas() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) = 0;
};

// An image as a canvas (row 0 at the top).
class ImageCanvas final : public Canvas {
public:
  explicit ImageCanvas(Image& image) : image_(image) {}
  int width() const override { return image_.width; }
  int height() const override { return image_.height; }
  void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) override;

private:
  Image& image_;
};

// Width and height in pixels of `text` drawn at `scale` (each font pixel a scale x scale block; a glyph cell
// is 6x8 font pixels including the gap).
int textWidth(const std::string& text, int scale);
inline int textHeight(int scale) {
  return 8 * scale;
}

// Draws `text` with its top-left corner at (x, y), opaque, clipped to the image.
void drawText(Canvas& canvas, int x, int y, const std::string& text, int scale, std::uint8_t r, std::uint8_t g,
              std::uint8_t b);
void drawText(Image& image, int x, int y, const std::string& text, int scale, std::uint8_t r, std::uint8_t g,
              std::uint8_t b);

// Fills a rectangle (clipped to the image) with an opaque colour.
void fillRect(Image& image, int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b);

} // namespace dtf::render
