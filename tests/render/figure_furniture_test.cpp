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
