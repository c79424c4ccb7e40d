// SPDX-License-Identifier: GPL-3.0-or-later
// The built-in 5x7 bitmap font that labels contact sheets: glyph shapes, size, colour and clipping.
#include "render/bitmap_text.h"

#include <gtest/gtest.h>

namespace {

using namespace dtf;

int lit(const Image& img, int x0, int y0, int w, int h) {
  int n = 0;
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x)
      n += img.pixel(x, y)[0] > 0;
  return n;
}

TEST(BitmapText, DrawsTheGlyphShapesAtScale) {
  Image img(40, 20);
  render::drawText(img, 1, 1, "1-", 2, 255, 10, 20);
  // '1' is 0x04,0x0C,0x04,0x04,0x04,0x04,0x0E: 10 font pixels, each 2x2.
  EXPECT_EQ(lit(img, 1, 1, 12, 16), 10 * 4);
  // Its stem is column 2 of rows 0..6; the top-left corner of the cell is empty.
  EXPECT_EQ(img.pixel(1 + 2 * 2, 1 + 2 * 3)[0], 255);
  EXPECT_EQ(img.pixel(1, 1)[0], 0);
  EXPECT_EQ(img.pixel(1 + 2 * 2, 1 + 2 * 3)[1], 10);
  EXPECT_EQ(img.pixel(1 + 2 * 2, 1 + 2 * 3)[3], 255);
  // '-' is one row of five font pixels, in the next 12-pixel cell.
  EXPECT_EQ(lit(img, 13, 1, 12, 16), 5 * 4);
  EXPECT_EQ(render::textWidth("1-", 2), 24);
  EXPECT_EQ(render::textHeight(2), 16);
}

// Lower case has glyphs of its own (a scale bar says mm, not MM); unknown characters draw as '?'.
TEST(BitmapText, LowercaseHasItsOwnGlyphsAndUnknownIsAQuestionMark) {
  Image a(12, 8), b(12, 8), c(12, 8), d(12, 8);
  render::drawText(a, 0, 0, "m", 1, 255, 255, 255);
  render::drawText(b, 0, 0, "M", 1, 255, 255, 255);
  EXPECT_NE(a.rgba, b.rgba);
  // 'm' is x-height: its top two rows are empty, 'M' starts at the top row.
  EXPECT_EQ(lit(a, 0, 0, 6, 2), 0);
  EXPECT_GT(lit(a, 0, 2, 6, 5), 8);
  EXPECT_GT(lit(b, 0, 0, 6, 1), 0);
  for (char l = 'a'; l <= 'z'; ++l) {
    Image low(6, 8), up(6, 8);
    render::drawText(low, 0, 0, std::string(1, l), 1, 255, 255, 255);
    render::drawText(up, 0, 0, std::string(1, static_cast<char>(l - 'a' + 'A')), 1, 255, 255, 255);
    EXPECT_GT(lit(low, 0, 0, 6, 8), 0) << l;
    EXPECT_NE(low.rgba, up.rgba) << l; // a shape of its own, not the capital drawn again
  }
  render::drawText(c, 0, 0, "~", 1, 255, 255, 255);
  render::drawText(d, 0, 0, "?", 1, 255, 255, 255);
  EXPECT_EQ(c.rgba, d.rgba);
  EXPECT_GT(lit(c, 0, 0, 12, 8), 0);
}

TEST(BitmapText, ClipsToTheImage) {
  Image img(8, 8);
  render::drawText(img, -3, -3, "WWW", 3, 255, 255, 255); // mostly outside: must not write out of bounds
  render::fillRect(img, 6, 6, 100, 100, 1, 2, 3);
  EXPECT_EQ(img.pixel(7, 7)[2], 3);
}

} // namespace
