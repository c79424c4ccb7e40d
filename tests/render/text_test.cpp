// SPDX-License-Identifier: GPL-3.0-or-later
// The figures' text (DejaVu Sans through FreeType): anti-aliased edges, sizes that scale, the ink where the
// metrics say, coverage blended over what is beneath (never opaque boxes), outlines, UTF-8, clipping, and
// drawing from several threads at once.
#include "render/text.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace dtf;
using render::FontSize;

Image filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image img(w, h);
  render::fillRect(img, 0, 0, w, h, r, g, b);
  return img;
}

// The box of pixels whose red channel differs from `background`: x0, y0, x1, y1 (exclusive); x0 = -1 if none.
std::array<int, 4> ink(const Image& img, std::uint8_t background) {
  std::array<int, 4> box{-1, -1, -1, -1};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (img.pixel(x, y)[0] != background) {
        if (box[0] < 0) box = {x, y, x + 1, y + 1};
        box = {std::min(box[0], x), std::min(box[1], y), std::max(box[2], x + 1), std::max(box[3], y + 1)};
      }
  return box;
}

TEST(Text, GlyphEdgesAreAntiAliased) {
  Image img = filled(120, 80, 0, 0, 0);
  render::drawText(img, 10, 10, "AR5", FontSize(40), 255, 255, 255);
  int full = 0, grey = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const int v = img.pixel(x, y)[0];
      full += v == 255;
      grey += v > 0 && v < 255;
      EXPECT_EQ(int(img.pixel(x, y)[3]), 255);
    }
  EXPECT_GT(full, 200); // the stems' insides are fully covered
  EXPECT_GT(grey, 60);  // the diagonals and curves' edges are partly covered
  // The diagonal of the A: along a row through its legs, coverage rises through several grey levels.
  std::vector<int> levels;
  for (int x = 10; x < 40; ++x)
    if (const int v = img.pixel(x, 25)[0]; v > 0 && v < 255) levels.push_back(v);
  EXPECT_GE(levels.size(), 2u);
}

TEST(Text, SizesScaleWithTheEm) {
  const std::string s = "Fractional anisotropy 0.25";
  const int w10 = render::textWidth(s, FontSize(10)), w20 = render::textWidth(s, FontSize(20)),
            w40 = render::textWidth(s, FontSize(40));
  EXPECT_NEAR(double(w20) / w10, 2.0, 0.12);
  EXPECT_NEAR(double(w40) / w20, 2.0, 0.06);
  // DejaVu Sans: capitals 0.73 em tall; the digit advance 0.636 em.
  EXPECT_EQ(render::textHeight(FontSize(100)), 73);
  EXPECT_NEAR(render::textWidth("0000000000", FontSize(100)), 636, 6);
  EXPECT_EQ(render::textWidth("", FontSize(20)), 0);
  // Fractional sizes lie between their neighbours.
  const int w15 = render::textWidth(s, FontSize(15.5));
  EXPECT_GT(w15, w10);
  EXPECT_LT(w15, w20);
}

TEST(Text, TheInkLiesWhereTheMetricsSay) {
  for (double px : {12.0, 24.0, 48.0}) {
    SCOPED_TRACE(px);
    const FontSize size(px);
    Image img = filled(400, 120, 0, 0, 0);
    const int x = 20, y = 30;
    render::drawText(img, x, y, "HELLO 123", size, 255, 255, 255);
    const auto box = ink(img, 0);
    ASSERT_GE(box[0], 0);
    // Capitals and digits fill [y, y + textHeight) to within a pixel (hinting); no descenders here.
    EXPECT_NEAR(box[1], y, 1);
    EXPECT_NEAR(box[3], y + render::textHeight(size), 1);
    // The ink spans the advance width less the side bearings (a few percent of the em at each end).
    EXPECT_NEAR(box[0], x, 0.1 * px + 1);
    EXPECT_NEAR(box[2], x + render::textWidth("HELLO 123", size), 0.15 * px + 1);
  }
  // A descender hangs below the baseline by at most textDescent.
  Image img = filled(200, 100, 0, 0, 0);
  render::drawText(img, 10, 20, "gjpqy", FontSize(40), 255, 255, 255);
  const auto box = ink(img, 0);
  EXPECT_GT(box[3], 20 + render::textHeight(FontSize(40)) + 4);
  EXPECT_LE(box[3], 20 + render::textHeight(FontSize(40)) + render::textDescent(FontSize(40)) + 1);
}

TEST(Text, CoverageBlendsOverWhatIsBeneath) {
  // White text over red: partly covered pixels are a mix (red kept, green and blue between), never a box.
  Image img = filled(100, 60, 255, 0, 0);
  render::drawText(img, 5, 10, "Wo", FontSize(36), 255, 255, 255);
  int mixed = 0, red = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      EXPECT_EQ(int(p[0]), 255);
      EXPECT_EQ(int(p[1]), int(p[2]));
      mixed += p[1] > 0 && p[1] < 255;
      red += p[1] == 0;
    }
  EXPECT_GT(mixed, 40);
  // Between the strokes of the W the red shows through: the text's bounding box is not filled.
  int redInsideBox = 0;
  for (int y = 10; y < 10 + render::textHeight(FontSize(36)); ++y)
    for (int x = 5; x < 5 + render::textWidth("Wo", FontSize(36)); ++x)
      redInsideBox += img.pixel(x, y)[1] == 0;
  EXPECT_GT(redInsideBox, 100);
  // Half coverage over half-transparent pixels: the image's alpha rises towards opaque.
  Image clear(40, 40);
  render::drawText(clear, 2, 5, "I", FontSize(30), 255, 255, 255);
  bool opaque = false;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      opaque = opaque || clear.pixel(x, y)[3] == 255;
      EXPECT_EQ(clear.pixel(x, y)[3] > 0, clear.pixel(x, y)[0] > 0);
    }
  EXPECT_TRUE(opaque);
}

TEST(Text, AnOutlineRingsTheGlyphsInBlack) {
  Image img = filled(120, 60, 255, 255, 255);
  render::drawOutlinedText(img, 10, 10, "L", FontSize(40), 2, 255, 255, 255);
  // White text on white: only the outline shows, a dark band around the L's stem (left of it).
  const auto box = ink(img, 255);
  ASSERT_GE(box[0], 0);
  int dark = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) dark += img.pixel(x, y)[0] < 64;
  EXPECT_GT(dark, 60);
  // The stem itself stays white.
  const Image plain = [] {
    Image p = filled(120, 60, 0, 0, 0);
    render::drawText(p, 10, 10, "L", FontSize(40), 255, 255, 255);
    return p;
  }();
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (plain.pixel(x, y)[0] == 255) {
        EXPECT_EQ(int(img.pixel(x, y)[0]), 255);
      }
    }
  // A two-pixel outline reaches beyond the glyph's own ink by two pixels on the left.
  EXPECT_EQ(box[0], ink(plain, 0)[0] - 2);
}

TEST(Text, Utf8AndMissingCharactersDraw) {
  // A degree sign (two bytes), a Greek letter, and a malformed byte (drawn as the replacement glyph).
  for (const std::string& s : {std::string("40\xC2\xB0"), std::string("\xCE\xBB"), std::string("a\xFFz")}) {
    Image img = filled(120, 60, 0, 0, 0);
    render::drawText(img, 5, 10, s, FontSize(30), 255, 255, 255);
    EXPECT_GE(ink(img, 0)[0], 0) << s;
    EXPECT_GT(render::textWidth(s, FontSize(30)), 0);
  }
  EXPECT_GT(render::textWidth("40\xC2\xB0", FontSize(30)), render::textWidth("40", FontSize(30)));
}

TEST(Text, ClipsToTheCanvas) {
  Image img = filled(20, 20, 0, 0, 0);
  render::drawText(img, -30, -25, "WWW", FontSize(60), 255, 255, 255); // mostly outside: no write out of bounds
  render::drawText(img, 15, 15, "WWW", FontSize(60), 255, 255, 255);
  render::drawOutlinedText(img, -5, 10, "Wg", FontSize(30), 3, 255, 255, 255);
  SUCCEED();
}

TEST(Text, ThreadsDrawTheSameText) {
  const auto draw = [](double px) {
    Image img = filled(200, 60, 0, 0, 0);
    render::drawOutlinedText(img, 4, 8, "Scale 20 mm", FontSize(px), 1, 255, 200, 100);
    return img.rgba;
  };
  std::vector<std::vector<std::uint8_t>> expected;
  for (int i = 0; i < 8; ++i) expected.push_back(draw(12.0 + i * 1.5));
  std::vector<std::thread> threads;
  std::vector<int> same(8, 0);
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 20; ++k) same[t] += draw(12.0 + t * 1.5) == expected[t];
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 8; ++t) EXPECT_EQ(same[t], 20);
}

} // namespace
