// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/figure_furniture.h"

#include "render/text.h"
#include "render/tract_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace dtf::render {

namespace {

// Text with a dark outline, readable over any fabric colour.
void outlinedText(Canvas& img, int x, int y, const std::string& text, FontSize size, std::uint8_t r,
                  std::uint8_t g, std::uint8_t b) {
  drawOutlinedText(img, x, y, text, size, std::max(1, static_cast<int>(std::lround(size.px / 12.0))), r, g, b);
}

// A line of `width` pixels from a to b (pixel centres), opaque.
void line(Canvas& img, glm::dvec2 a, glm::dvec2 b, int width, const std::uint8_t c[3]) {
  const double len = glm::length(b - a);
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2)));
  for (int s = 0; s <= steps; ++s) {
    const glm::dvec2 p = a + (b - a) * (static_cast<double>(s) / steps);
    img.fill(static_cast<int>(std::lround(p.x)) - width / 2, static_cast<int>(std::lround(p.y)) - width / 2,
             width, width, c[0], c[1], c[2]);
  }
}

// An opaque black panel with a grey one-pixel frame behind a legend, so that it reads over the fabric or
// tracts it may cover as over the background.
void backing(Canvas& img, int x, int y, int w, int h) {
  img.fill(x, y, w, h, 90, 90, 90);
  img.fill(x + 1, y + 1, w - 2, h - 2, 0, 0, 0);
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

int furnitureScale(int width, int height) {
  return std::max(std::min(width, height) / 256, 1);
}

FontSize furnitureFont(int width, int height) {
  return FontSize(11.0 * std::max(std::min(width, height) / 256.0, 1.0));
}

FontSize letterFont(int width, int height) {
  return FontSize(2.0 * furnitureFont(width, height).px);
}

int letterBand(int width, int height) {
  const int scale = furnitureScale(width, height);
  const FontSize letter = letterFont(width, height);
  // drawFurniture's margin, the letter and a gap.
  return 4 * scale + std::max(textHeight(letter), textWidth("M", letter)) + 2 * scale;
}

void drawFurniture(Image& image, const Camera& camera, double pixelMm, const FigureFurniture& what) {
  ImageCanvas canvas(image);
  drawFurniture(canvas, camera, pixelMm, what);
}

void drawColourBar(Image& image, const ValueColourBar& bar) {
  ImageCanvas canvas(image);
  drawColourBar(canvas, bar);
}

void drawPaneDivider(Canvas& img, int x) {
  const int width = 2 * std::max(1, furnitureScale(img.width(), img.height()) / 2);
  img.fill(x - width / 2, 0, width, img.height(), 90, 90, 90);
}

void drawPaneDivider(Image& image, int x) {
  ImageCanvas canvas(image);
  drawPaneDivider(canvas, x);
}

std::pair<std::string, std::string> colourBarLabels(double lo, double hi) {
  const double span = std::abs(hi - lo), big = std::max(std::abs(lo), std::abs(hi));
  int decimals = -1; // %.3g
  if (span > 0 && std::isfinite(span) && big < 1e6)
    decimals = std::max(0, 1 - static_cast<int>(std::floor(std::log10(span))));
  if (decimals > 6) decimals = -1;
  auto text = [decimals](double v) {
    char buf[48];
    if (decimals < 0)
      std::snprintf(buf, sizeof buf, "%.3g", v);
    else
      std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return std::string(buf);
  };
  return {text(lo), text(hi)};
}

void drawColourBar(Canvas& img, const ValueColourBar& bar) {
  const int w = img.width(), h = img.height();
  if (w < 64 || h < 64) return;
  const int scale = furnitureScale(w, h);
  const int barW = std::max(8, w / 64), barH = std::max(16, h * 2 / 5);
  const auto labels = colourBarLabels(bar.lo, bar.hi);
  const std::string &lo = labels.first, &hi = labels.second;
  const FontSize font = furnitureFont(w, h);
  const int th = textHeight(font), gap = 3 * scale, pad = 2 * scale + 1;
  // The panel ends inside the band of the orientation letter at the right edge's middle (drawFurniture's
  // margin and size).
  const int x0 = w - 4 * scale - textWidth("M", letterFont(w, h)) - 4 * scale - barW - pad, y0 = (h - barH) / 2;
  const int labelsLeft = x0 - gap - std::max(textWidth(hi, font), textWidth(lo, font));
  const int panelLeft = std::max(0, std::min(labelsLeft, x0 + barW - textWidth(bar.name, font)) - pad);
  const int panelTop = y0 - (bar.name.empty() ? 1 : gap + th) - pad;
  backing(img, panelLeft, panelTop, x0 + barW + 1 + pad - panelLeft, y0 + barH + 1 + pad - panelTop);
  img.fill(x0 - 1, y0 - 1, barW + 2, barH + 2, 255, 255, 255);
  for (int y = 0; y < barH; ++y) {
    const glm::vec3 c = tractValueColour(1.0f - float(y) / float(std::max(barH - 1, 1)));
    img.fill(x0, y0 + y, barW, 1, static_cast<std::uint8_t>(std::lround(c.x * 255.0f)),
             static_cast<std::uint8_t>(std::lround(c.y * 255.0f)),
             static_cast<std::uint8_t>(std::lround(c.z * 255.0f)));
  }
  outlinedText(img, x0 - gap - textWidth(hi, font), y0, hi, font, 255, 255, 255);
  outlinedText(img, x0 - gap - textWidth(lo, font), y0 + barH - th, lo, font, 255, 255, 255);
  if (!bar.name.empty())
    outlinedText(img, std::max(0, x0 + barW - textWidth(bar.name, font)), y0 - gap - th, bar.name, font, 255,
                 255, 255);
}

void drawFurniture(Canvas& img, const Camera& camera, double pixelMm, const FigureFurniture& what) {
  const int w = img.width(), h = img.height();
  if (w < 32 || h < 32) return;
  const int scale = furnitureScale(w, h);
  const FontSize font = furnitureFont(w, h), big = letterFont(w, h);
  const int margin = 4 * scale;
  const glm::dvec3 right = camera.right(), up = glm::normalize(glm::cross(right, camera.forward()));
  if (what.letters) {
    const std::string r(1, anatomicalLetter(right)), l(1, anatomicalLetter(-right)),
        t(1, anatomicalLetter(up)), b(1, anatomicalLetter(-up));
    // Each letter centred in a box as wide as an M (the widest letter), the capitals' height tall.
    const int tw = textWidth("M", big), th = textHeight(big);
    const auto at = [&](const std::string& letter, int x, int y) {
      outlinedText(img, x + (tw - textWidth(letter, big)) / 2, y, letter, big, 255, 255, 255);
    };
    at(l, margin, (h - th) / 2);
    at(r, w - margin - tw, (h - th) / 2);
    at(t, (w - tw) / 2, margin);
    at(b, (w - tw) / 2, h - margin - th);
  }
  if (what.scaleBar && pixelMm > 0) {
    const double mm = scaleBarMm(w, pixelMm);
    const int px = static_cast<int>(std::lround(mm / pixelMm));
    if (mm > 0 && px >= 8) {
      char label[32];
      std::snprintf(label, sizeof label, "%g mm", mm);
      const int y = h - margin - 3 * scale - what.bottomLeftReserved;
      img.fill(margin - 1, y - 1, px + 2, 3 * scale + 2, 0, 0, 0);
      img.fill(margin, y, px, 3 * scale, 255, 255, 255);
      outlinedText(img, margin, y - textHeight(font) - 3 * scale, label, font, 255, 255, 255);
    }
  }
  if (what.legend) {
    // The world axes as the camera shows them (orthographic: the in-image part of each), in DEC colours,
    // each labelled with its positive side; axes pointing along the view are drawn short.
    // On a square panel `margin` pixels from the bottom and right edges, wide enough for the axes and the
    // letters at their tips.
    const double radius = 14.0 * scale;
    const int half = static_cast<int>(radius) + 3 * scale + std::max(textWidth("M", font), textHeight(font)) + scale;
    // An image too small to hold the panel without hiding much of the data (a third of its smaller side)
    // goes without it.
    if (3 * (2 * half + 1) > std::min(w, h)) return;
    const glm::dvec2 centre(w - margin - 1 - half, h - margin - 1 - half);
    backing(img, static_cast<int>(centre.x) - half, static_cast<int>(centre.y) - half, 2 * half + 1,
            2 * half + 1);
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
        outlinedText(img, static_cast<int>(tip.x + 3 * d.x * scale) - textWidth(letter, font) / 2,
                     static_cast<int>(tip.y + 3 * d.y * scale) - textHeight(font) / 2, letter, font,
                     colours[i][0], colours[i][1], colours[i][2]);
    }
  }
}

} // namespace dtf::render
