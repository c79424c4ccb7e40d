// A small built-in 5x7 bitmap font for labelling rendered images on the CPU (contact sheets, panel
// captions): no font files, no GL. Letters are drawn as capitals; characters without a glyph draw as '?'.
#pragma once

#include "io/model/image.h"

#include <cstdint>
#include <string>

namespace dtf::render {

// Width and height in pixels of `text` drawn at `scale` (each font pixel a scale x scale block; a glyph cell
// is 6x8 font pixels including the gap).
int textWidth(const std::string& text, int scale);
inline int textHeight(int scale) {
  return 8 * scale;
}

// Draws `text` with its top-left corner at (x, y), opaque, clipped to the image.
void drawText(Image& image, int x, int y, const std::string& text, int scale, std::uint8_t r, std::uint8_t g,
              std::uint8_t b);

// Fills a rectangle (clipped to the image) with an opaque colour.
void fillRect(Image& image, int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b);

} // namespace dtf::render
