// What a figure carries besides the fabric, drawn on the CPU into a rendered still (row 0 at the top):
// orientation letters at the four edges (the anatomical side the camera puts there, so radiological and
// neurological views are labelled as shown), a medical-colour orientation legend (the world axes through the
// camera: R/L red, A/P green, S/I blue, as the DEC colours) and a scale bar in mm. No GL.
#pragma once

#include "io/model/image.h"
#include "render/camera.h"

namespace dtf::render {

struct FigureFurniture {
  bool letters = true;  // L/R, A/P, S/I at the edges
  bool legend = true;   // the RGB axes glyph, bottom right
  bool scaleBar = true; // a bar of a round length in mm, bottom left (orthographic views only)
};

// The anatomical letter of a world direction's dominant axis: R/L (x), A/P (y), S/I (z).
char anatomicalLetter(const glm::dvec3& direction);
// The scale bar's length in mm for an image `widthPx` wide at `pixelMm`: 1, 2 or 5 x 10^k, about a fifth of
// the width.
double scaleBarMm(int widthPx, double pixelMm);
// Draws the furniture asked for. `pixelMm`: the pixel size in mm at the camera's target (orthographic).
void drawFurniture(Image& image, const Camera& camera, double pixelMm, const FigureFurniture& what);

} // namespace dtf::render
