// SPDX-License-Identifier: GPL-3.0-or-later
// The figure's furniture on the CPU: letters name the side the camera puts at each edge (radiological and
// neurological), the scale bar is as long as its label says, the legend is drawn in DEC colours, and each
// piece appears only where asked.
#include "render/figure_furniture.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace dtf;
using namespace dtf::render;

namespace {

constexpr int kSize = 512;

Camera axial(bool neurological) {
  return Camera::standard(StandardView::Inferior, {-80, -100, -40}, {80, 100, 60}, 1.0, neurological, true);
}

// Pixels in [x0, x1) x [y0, y1) that are not black.
int lit(const Image& img, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      if (img.pixel(x, y)[0] || img.pixel(x, y)[1] || img.pixel(x, y)[2]) ++n;
  return n;
}

Image black() {
  Image img(kSize, kSize);
  for (std::size_t i = 3; i < img.rgba.size(); i += 4)
    img.rgba[i] = 255;
  return img;
}

} // namespace

TEST(FigureFurniture, LettersFollowTheDisplayConvention) {
  // Radiological axial (seen from below): the patient's right on the image left.
  const Camera radio = Camera::standard(StandardView::Inferior, {-80, -100, -40}, {80, 100, 60}, 1.0);
  EXPECT_EQ(anatomicalLetter(radio.right()), 'L');
  EXPECT_EQ(anatomicalLetter(-radio.right()), 'R');
  const Camera neuro = Camera::standard(StandardView::Superior, {-80, -100, -40}, {80, 100, 60}, 1.0);
  EXPECT_EQ(anatomicalLetter(neuro.right()), 'R');
  const Camera coronal = Camera::standard(StandardView::Anterior, {-80, -100, -40}, {80, 100, 60}, 1.0);
  EXPECT_EQ(anatomicalLetter(coronal.right()), 'L');
  EXPECT_EQ(anatomicalLetter(coronal.up), 'S');
}

TEST(FigureFurniture, ScaleBarIsARoundLengthAboutAFifthOfTheWidth) {
  EXPECT_DOUBLE_EQ(scaleBarMm(500, 0.4), 20.0); // 40 mm -> 20
  EXPECT_DOUBLE_EQ(scaleBarMm(768, 0.3), 20.0); // 46 mm -> 20
  EXPECT_DOUBLE_EQ(scaleBarMm(256, 1.0), 50.0); // 51 mm -> 50
  EXPECT_DOUBLE_EQ(scaleBarMm(1000, 0.1), 20.0); // exactly 20 mm
  EXPECT_DOUBLE_EQ(scaleBarMm(1000, 0.09), 10.0); // 18 mm -> 10
}

TEST(FigureFurniture, EachPieceIsDrawnWhereAskedAndAbsentWhenNot) {
  const double pixelMm = 0.4;
  const int edge = 40; // the letters' band
  for (int piece = 0; piece < 3; ++piece) {
    SCOPED_TRACE(piece);
    FigureFurniture only{piece == 0, piece == 1, piece == 2};
    Image img = black();
    drawFurniture(img, axial(false), pixelMm, only);
    const int left = lit(img, 0, kSize / 2 - edge, edge, kSize / 2 + edge);
    const int right = lit(img, kSize - edge, kSize / 2 - edge, kSize, kSize / 2 + edge);
    const int top = lit(img, kSize / 2 - edge, 0, kSize / 2 + edge, edge);
    const int legend = lit(img, kSize - 120, kSize - 120, kSize - edge, kSize);
    const int bar = lit(img, 0, kSize - 60, kSize / 3, kSize);
    EXPECT_EQ(left > 0 && right > 0 && top > 0, piece == 0);
    EXPECT_EQ(legend > 0, piece == 1);
    EXPECT_EQ(bar > 0, piece == 2);
    // Nothing elsewhere: the middle of the image stays black.
    EXPECT_EQ(lit(img, kSize / 4, kSize / 4, 3 * kSize / 4, 3 * kSize / 4), 0);
  }
  Image none = black();
  drawFurniture(none, axial(false), pixelMm, {false, false, false});
  EXPECT_EQ(lit(none, 0, 0, kSize, kSize), 0);
}

TEST(FigureFurniture, TheScaleBarIsAsLongAsItsLabel) {
  const double pixelMm = 0.4;
  Image img = black();
  drawFurniture(img, axial(false), pixelMm, {false, false, true});
  // The bar: the longest run of white pixels in a row near the bottom.
  int longest = 0;
  for (int y = kSize - 30; y < kSize; ++y) {
    int run = 0;
    for (int x = 0; x < kSize; ++x) {
      const auto* c = img.pixel(x, y);
      run = c[0] == 255 && c[1] == 255 && c[2] == 255 ? run + 1 : 0;
      longest = std::max(longest, run);
    }
  }
  EXPECT_EQ(longest, static_cast<int>(std::lround(scaleBarMm(kSize, pixelMm) / pixelMm)));
}

TEST(FigureFurniture, TheLegendShowsTheInPlaneAxesInTheirDecColours) {
  Image img = black();
  drawFurniture(img, axial(false), 0.4, {false, true, false});
  int red = 0, green = 0, blue = 0;
  for (int y = kSize - 120; y < kSize; ++y)
    for (int x = kSize - 120; x < kSize; ++x) {
      const auto* c = img.pixel(x, y);
      if (c[0] > 150 && c[1] < 100 && c[2] < 100) ++red;
      if (c[1] > 150 && c[0] < 100 && c[2] < 100) ++green;
      if (c[2] > 150 && c[0] < 100 && c[1] < 150) ++blue;
    }
  EXPECT_GT(red, 20);   // R-L lies in an axial image
  EXPECT_GT(green, 20); // A-P too
  EXPECT_LT(blue, red / 2); // S-I points along the view: a dot at most
}

TEST(FigureFurniture, TheColourBarShowsTheMapWithItsRangeAndName) {
  Image img = black();
  drawColourBar(img, {"FA", 0.2, 0.85});
  // The bar: 8 px wide, 204 px tall centred, its panel ending beside the band of the orientation letter at
  // the right edge (nothing drawn in that band); top #fde725, bottom #440154.
  const int y0 = (kSize - 204) / 2, band = letterBand(kSize, kSize);
  int right = -1; // the bar's rightmost column: the first coloured pixel from the right on its middle row
  for (int xx = kSize - 1; xx >= 0 && right < 0; --xx) {
    const std::uint8_t* c = img.pixel(xx, y0 + 102);
    if (c[0] != c[1] || c[1] != c[2]) right = xx;
  }
  ASSERT_GT(right, kSize - 2 * band);
  EXPECT_LT(right, kSize - band);
  EXPECT_EQ(lit(img, kSize - band, 0, kSize, kSize), 0); // the letter band stays free
  const int x = right - 4;
  const std::uint8_t* top = img.pixel(x, y0);
  const std::uint8_t* bottom = img.pixel(x, y0 + 203);
  EXPECT_EQ(int(top[0]), 0xfd);
  EXPECT_EQ(int(top[1]), 0xe7);
  EXPECT_EQ(int(top[2]), 0x25);
  EXPECT_EQ(int(bottom[0]), 0x44);
  EXPECT_EQ(int(bottom[1]), 0x01);
  EXPECT_EQ(int(bottom[2]), 0x54);
  // Labels: the high value beside the top, the low one beside the bottom, the name above; white text (the
  // glyphs' insides fully covered).
  auto white = [&](int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int yy = y0; yy < y1; ++yy)
      for (int xx = x0; xx < x1; ++xx)
        n += img.pixel(xx, yy)[0] == 255 && img.pixel(xx, yy)[1] == 255 && img.pixel(xx, yy)[2] == 255;
    return n;
  };
  const int th = textHeight(furnitureFont(kSize, kSize));
  EXPECT_GT(white(x - 90, y0, x - 6, y0 + th), 10);                   // "0.85"
  EXPECT_GT(white(x - 90, y0 + 204 - th, x - 6, y0 + 204), 10);       // "0.20"
  EXPECT_GT(white(x - 60, y0 - 2 * th - 6, x + 10, y0 - 2), 10);      // "FA"
  EXPECT_EQ(white(x - 90, y0 + th + 8, x - 6, y0 + 204 - th - 8), 0); // no label between them
  EXPECT_EQ(lit(img, 0, 0, x - 100, kSize), 0);                       // nothing else

  // Over a white fabric the bar sits on its black panel with a grey frame: between the labels and the bar,
  // and below the bar, the fabric is covered; outside the panel it is not.
  Image fabric(kSize, kSize);
  std::fill(fabric.rgba.begin(), fabric.rgba.end(), std::uint8_t(255));
  drawColourBar(fabric, {"FA", 0.2, 0.85});
  auto grey = [&](int xx, int yy) { return int(fabric.pixel(xx, yy)[0]); };
  EXPECT_EQ(grey(x - 6, y0 + 100), 0);        // between the labels and the bar
  EXPECT_EQ(grey(x, y0 + 204 + 2), 0);        // below the bar's frame
  EXPECT_EQ(grey(x, y0 + 204 + 5), 90);       // the panel's frame
  EXPECT_EQ(grey(x, y0 + 204 + 6), 255);      // the fabric beyond it
  EXPECT_EQ(grey(kSize - band, y0 + 100), 255); // the letter band is not covered
}

// Both ends of the bar written alike, with the decimals the range needs: "0.2" against "0.85" read as
// numbers of different precision, and %.3g gave a tract length 187.6 as "188" beside "10.3".
TEST(FigureFurniture, TheColourBarLabelsShareTheirPrecision) {
  using P = std::pair<std::string, std::string>;
  EXPECT_EQ(colourBarLabels(0.2, 0.85), P("0.20", "0.85"));         // FA
  EXPECT_EQ(colourBarLabels(10.3, 187.6), P("10", "188"));          // length, mm
  EXPECT_EQ(colourBarLabels(0.0005, 0.003), P("0.0005", "0.0030")); // MD, mm^2/s
  EXPECT_EQ(colourBarLabels(0.31, 0.34), P("0.310", "0.340"));      // a narrow range keeps two digits of it
  EXPECT_EQ(colourBarLabels(-1, 1), P("-1.0", "1.0"));
  EXPECT_EQ(colourBarLabels(0.5, 0.5), P("0.5", "0.5"));       // no range: %.3g
  EXPECT_EQ(colourBarLabels(1e-9, 3e-9), P("1e-09", "3e-09")); // beyond six decimals: %.3g
  EXPECT_EQ(colourBarLabels(0, 2.5e6), P("0", "2.5e+06"));
}

TEST(FigureFurniture, ThePaneDividerIsAGreyLineOnTheSeam) {
  Image img = black();
  drawPaneDivider(img, kSize / 2);
  for (int y : {0, kSize / 2, kSize - 1}) {
    EXPECT_EQ(int(img.pixel(kSize / 2 - 1, y)[1]), 90);
    EXPECT_EQ(int(img.pixel(kSize / 2, y)[1]), 90);
  }
  EXPECT_EQ(lit(img, 0, 0, kSize / 2 - 1, kSize), 0);
  EXPECT_EQ(lit(img, kSize / 2 + 1, 0, kSize, kSize), 0);
  Image wide(2048, 1024);
  drawPaneDivider(wide, 1024);
  EXPECT_EQ(int(wide.pixel(1022, 10)[0]), 90); // 4 pixels when the smaller side is 1024 or more
  EXPECT_EQ(int(wide.pixel(1025, 10)[0]), 90);
  EXPECT_EQ(int(wide.pixel(1026, 10)[0]), 0);
}

TEST(FigureFurniture, AReservedCornerLiftsTheScaleBar) {
  FigureFurniture bar{false, false, true};
  Image low = black(), lifted = black();
  drawFurniture(low, axial(false), 0.4, bar);
  bar.bottomLeftReserved = 100;
  drawFurniture(lifted, axial(false), 0.4, bar);
  EXPECT_GT(lit(low, 0, kSize - 40, kSize / 3, kSize), 0);
  EXPECT_EQ(lit(lifted, 0, kSize - 100, kSize / 3, kSize), 0);
  EXPECT_GT(lit(lifted, 0, kSize - 140, kSize / 3, kSize - 100), 0);
}
