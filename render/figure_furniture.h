// SPDX-License-Identifier: GPL-3.0-or-later
// What a figure carries besides the fabric, drawn on the CPU into a rendered still (row 0 at the top):
// orientation letters at the four edges (the anatomical side the camera puts there, so radiological and
// neurological views are labelled as shown), a medical-colour orientation legend (the world axes through the
// camera: R/L red, A/P green, S/I blue, as the DEC colours), a scale bar in mm and the colour bar of a tract
// value. Drawn on a Canvas (render/text.h): an image, or the viewer's overlay over its panes. No GL.
#pragma once

#include "io/model/image.h"
#include "render/text.h"
#include "render/camera.h"

#include <string>
#include <utility>

namespace dtf::render {

struct FigureFurniture {
  bool letters = true;   // L/R, A/P, S/I at the edges
  bool legend = true;    // the RGB axes glyph, bottom right
  bool scaleBar = true;  // a bar of a round length in mm, bottom left (orthographic views only)
  bool colourBar = true; // the tract value's colour bar, right edge (when tracts are coloured by a value)
  int bottomLeftReserved = 0; // pixels above the bottom edge kept free at the left (another legend there)
};

// The colour bar of tracts coloured by a value (drawColourBar).
struct ValueColourBar {
  std::string name;      // the value's name
  double lo = 0, hi = 1; // the values at the colour map's ends
};

// The anatomical letter of a world direction's dominant axis: R/L (x), A/P (y), S/I (z).
char anatomicalLetter(const glm::dvec3& direction);
// The scale bar's length in mm for an image `widthPx` wide at `pixelMm`: 1, 2 or 5 x 10^k, about a fifth of
// the width.
double scaleBarMm(int widthPx, double pixelMm);
// The furniture's layout unit in pixels (margins, line widths) on a canvas of this size: 1 up to 511 pixels,
// then one more per 256 pixels of the smaller side.
int furnitureScale(int width, int height);
// The size of the furniture's labels on a canvas of this size: 11 pixels to the em up to 256 pixels, then in
// proportion to the smaller side, so a figure's layout is the same at any size. The orientation letters are
// twice that (letterFont).
FontSize furnitureFont(int width, int height);
FontSize letterFont(int width, int height);
// The band at each edge of a canvas this size that the orientation letters take, in pixels from the edge:
// content framed inside it leaves the letters over the background.
int letterBand(int width, int height);
// Draws the furniture asked for. `pixelMm`: the pixel size in mm at the camera's target (orthographic).
void drawFurniture(Canvas& canvas, const Camera& camera, double pixelMm, const FigureFurniture& what);
void drawFurniture(Image& image, const Camera& camera, double pixelMm, const FigureFurniture& what);
// The tract colour map (render/tract_renderer.h tractValueColour) as a vertical bar at the right edge, low
// at the bottom, framed in white, labelled with `bar.hi` at its top, `bar.lo` at its bottom and the value's
// name above it.
void drawColourBar(Canvas& canvas, const ValueColourBar& bar);
void drawColourBar(Image& image, const ValueColourBar& bar);
// The seam between panes side by side in one image (a split view): a grey (90) line, 2 pixels wide (4 on a
// canvas whose smaller side is 1024 pixels or more), centred on column `x`, over the panes' edge pixels.
void drawPaneDivider(Canvas& canvas, int x);
void drawPaneDivider(Image& image, int x);
// The colour bar's two labels (lo, hi), written alike: fixed point with the decimals that show two
// significant digits of the range (0.10 and 0.85, 20 and 150, 0.0005 and 0.0030), or both in %.3g where
// that would need more than six decimals or the values reach a million.
std::pair<std::string, std::string> colourBarLabels(double lo, double hi);

} // namespace dtf::render
