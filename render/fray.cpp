// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fray.h"

#include "render/text.h"

#include <cmath>
#include <string>

namespace dtf::render {

std::uint32_t frayHash(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

float frayDraw(glm::vec3 world, glm::vec3 origin, float lod, float cells, std::uint32_t salt) {
  const glm::vec3 f = glm::floor((world - origin) / lod * cells);
  const auto u = [](float v) { return static_cast<std::uint32_t>(static_cast<std::int32_t>(v)); };
  const std::uint32_t h = frayHash(u(f.x) ^ frayHash(u(f.y) ^ frayHash(u(f.z) ^ frayHash(salt))));
  return static_cast<float>(h >> 8) * (2.0f / 16777215.0f) - 1.0f;
}

float frayAngle(glm::vec3 world, glm::vec3 origin, float lod, float cells, float coneDeg, float fray,
                std::uint32_t salt) {
  return frayDraw(world, origin, lod, cells, salt) * fray * glm::radians(coneDeg);
}

namespace {

// An anti-aliasing-free line of width `w` pixels from a to b.
void stroke(Canvas& im, glm::vec2 a, glm::vec2 b, int w, std::uint8_t r, std::uint8_t g, std::uint8_t bl) {
  const float len = glm::length(b - a);
  const int steps = std::max(1, static_cast<int>(len * 2));
  for (int i = 0; i <= steps; ++i) {
    const glm::vec2 p = a + (b - a) * (static_cast<float>(i) / steps);
    im.fill(static_cast<int>(p.x) - w / 2, static_cast<int>(p.y) - w / 2, w, w, r, g, bl);
  }
}

} // namespace

ScalarVolume slotCones(const FibreSet& set, const FibreSet& slotted, const ScalarVolume& cones) {
  ScalarVolume out(slotted.grid, 3);
  const std::size_t n = slotted.grid.voxelCount(), k = static_cast<std::size_t>(set.maxFibres),
                    ks = static_cast<std::size_t>(slotted.maxFibres), kc = static_cast<std::size_t>(cones.components);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t j = 0; j < std::min<std::size_t>(ks, 3); ++j) {
      const Fibre& s = slotted.fibres[v * ks + j];
      if (!(s.amplitude > 0.0f)) continue;
      float best = -1.0f;
      for (std::size_t i = 0; i < std::min(k, kc); ++i) {
        const Fibre& f = set.fibres[v * k + i];
        const float c = std::abs(glm::dot(f.direction, s.direction));
        if (f.amplitude == s.amplitude && c > best) {
          best = c;
          const float cone = cones.data[v * kc + i];
          out.data[v * 3 + j] = std::isfinite(cone) ? cone : 0.0f;
        }
      }
    }
  return out;
}

namespace {

FontSize legendFont(int scale) {
  return FontSize(11.0 * scale);
}

} // namespace

int frayLegendHeight(int scale) {
  return 18 * scale + 2 * textHeight(legendFont(scale)) + 4 * 4 * scale + 3 * scale;
}

void drawFrayLegend(Image& image, float fray, int scale) {
  ImageCanvas canvas(image);
  drawFrayLegend(canvas, fray, scale);
}

void drawFrayLegend(Canvas& image, float fray, int scale) {
  const float cones[] = {0, 10, 20, 40};
  const int box = 18 * scale, gap = 4 * scale, pad = 3 * scale;
  const std::string caption = "95% cone (deg)";
  const FontSize font = legendFont(scale);
  const int width = std::max(4 * box + 5 * gap, textWidth(caption, font) + 2 * gap);
  const int height = box + 2 * textHeight(font) + 4 * gap;
  const int x0 = pad, y0 = image.height() - height - pad;
  if (x0 + width > image.width() || y0 < 0) return; // too small an image for a legend
  image.fill(x0, y0, width, height, 0, 0, 0);
  drawText(image, x0 + gap, y0 + gap, caption, font, 255, 255, 255);
  const int by = y0 + 2 * gap + textHeight(font);
  for (int c = 0; c < 4; ++c) {
    const int bx = x0 + gap + c * (box + gap);
    image.fill(bx, by, box, box, 40, 40, 40);
    // A 3x4 grid of cells, each a horizontal thread turned by its cell's draw, as the renderer turns them.
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        const float a = frayAngle(glm::vec3(i, j, 0), glm::vec3(0), 1, 1, cones[c], fray, 7);
        const glm::vec2 centre(bx + (i + 0.5f) * box / 3.0f, by + (j + 0.5f) * box / 4.0f);
        const glm::vec2 d = 0.5f * box / 3.0f * glm::vec2(std::cos(a), -std::sin(a));
        stroke(image, centre - d, centre + d, std::max(1, scale), 230, 230, 230);
      }
    const std::string label = std::to_string(static_cast<int>(cones[c]));
    drawText(image, bx + (box - textWidth(label, font)) / 2, by + box + gap, label, font, 255, 255, 255);
  }
}

} // namespace dtf::render
