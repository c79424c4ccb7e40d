#include "render/figure_furniture.h"

#include "render/bitmap_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace dtf::render {

namespace {

// Text with a one-pixel dark outline, readable over any fabric colour.
void outlinedText(Image& img, int x, int y, const std::string& text, int scale, std::uint8_t r, std::uint8_t g,
                  std::uint8_t b) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx || dy) drawText(img, x + dx * std::max(1, scale / 2), y + dy * std::max(1, scale / 2), text, scale, 0, 0, 0);
  drawText(img, x, y, text, scale, r, g, b);
}

// A line of `width` pixels from a to b (pixel centres), opaque.
void line(Image& img, glm::dvec2 a, glm::dvec2 b, int width, const std::uint8_t c[3]) {
  const double len = glm::length(b - a);
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2)));
  for (int s = 0; s <= steps; ++s) {
    const glm::dvec2 p = a + (b - a) * (static_cast<double>(s) / steps);
    fillRect(img, static_cast<int>(std::lround(p.x)) - width / 2, static_cast<int>(std::lround(p.y)) - width / 2,
             width, width, c[0], c[1], c[2]);
  }
}

} // namespace

char anatomicalLetter(const glm::dvec3& d) {
  const glm::dvec3 a = glm::abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0 ? 'R' : 'L';
  if (a.y >= a.z) return d.y >= 0 ? 'A' : 'P';
  return d.z >= 0 ? 'S' : 'I';
}

double scaleBarMm(int widthPx, double pixelMm) {
  const double target = 0.2 * widthPx * pixelMm;
  if (!(target > 0) || !std::isfinite(target)) return 0;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double best = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade <= target) best = m * decade;
  return best;
}

void drawFurniture(Image& img, const Camera& camera, double pixelMm, const FigureFurniture& what) {
  const int w = img.width, h = img.height;
  if (w < 32 || h < 32) return;
  const int scale = std::clamp(std::min(w, h) / 256, 1, 4);
  const int margin = 4 * scale;
  const glm::dvec3 right = camera.right(), up = glm::normalize(glm::cross(right, camera.forward()));
  if (what.letters) {
    const std::string r(1, anatomicalLetter(right)), l(1, anatomicalLetter(-right)), t(1, anatomicalLetter(up)),
        b(1, anatomicalLetter(-up));
    const int tw = textWidth("M", scale * 2), th = textHeight(scale * 2);
    outlinedText(img, margin, (h - th) / 2, l, scale * 2, 255, 255, 255);
    outlinedText(img, w - margin - tw, (h - th) / 2, r, scale * 2, 255, 255, 255);
    outlinedText(img, (w - tw) / 2, margin, t, scale * 2, 255, 255, 255);
    outlinedText(img, (w - tw) / 2, h - margin - th, b, scale * 2, 255, 255, 255);
  }
  if (what.scaleBar && pixelMm > 0) {
    const double mm = scaleBarMm(w, pixelMm);
    const int px = static_cast<int>(std::lround(mm / pixelMm));
    if (mm > 0 && px >= 8) {
      char label[32];
      std::snprintf(label, sizeof label, "%g MM", mm);
      const int y = h - margin - 3 * scale;
      fillRect(img, margin - 1, y - 1, px + 2, 3 * scale + 2, 0, 0, 0);
      fillRect(img, margin, y, px, 3 * scale, 255, 255, 255);
      outlinedText(img, margin, y - textHeight(scale) - 2 * scale, label, scale, 255, 255, 255);
    }
  }
  if (what.legend) {
    // The world axes as the camera shows them (orthographic: the in-image part of each), in DEC colours,
    // each labelled with its positive side; axes pointing along the view are drawn short.
    const double radius = 14.0 * scale;
    const glm::dvec2 centre(w - margin - radius - textWidth("M", scale) - 2, h - margin - radius - textHeight(scale));
    const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::uint8_t colours[3][3] = {{230, 40, 40}, {40, 210, 40}, {60, 90, 255}};
    const std::uint8_t black[3] = {0, 0, 0};
    // Farthest first, so the axis nearest the viewer is drawn on top.
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) {
      return glm::dot(axes[a], camera.forward()) > glm::dot(axes[b], camera.forward());
    });
    for (int i : order) {
      const glm::dvec2 d(glm::dot(axes[i], right), -glm::dot(axes[i], up)); // image y grows downwards
      const glm::dvec2 tip = centre + radius * d;
      line(img, centre, tip, scale + 2, black);
      line(img, centre, tip, scale, colours[i]);
      const std::string letter(1, anatomicalLetter(axes[i]));
      if (glm::length(d) > 0.3)
        outlinedText(img, static_cast<int>(tip.x + 3 * d.x * scale) - textWidth(letter, scale) / 2,
                     static_cast<int>(tip.y + 3 * d.y * scale) - textHeight(scale) / 2, letter, scale, colours[i][0],
                     colours[i][1], colours[i][2]);
    }
  }
}

} // namespace dtf::render
