// SPDX-License-Identifier: GPL-3.0-or-later
// Text and filled shapes for labelling rendered images on the CPU: the figures' furniture (letters, legends,
// scale and colour bars), contact sheets and panel captions. Text is DejaVu Sans rasterised anti-aliased by
// FreeType (kept private to this library's sources) at the size asked for, in pixels; glyphs are cached per
// size. No GL: a Canvas is an image or a host's 2D draw list (the viewer draws the same furniture over its
// panes with ImGui).
#pragma once

#include "io/model/image.h"

#include <cstdint>
#include <string>

namespace dtf::render {

// Where labels and figure furniture are drawn: an image, or a host's 2D draw list. Rectangles, opaque or
// blended over what is there; text arrives as runs of pixels of one coverage. Clipped to the canvas.
class Canvas {
public:
  virtual ~Canvas() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  // An opaque rectangle.
  virtual void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) = 0;
  // A rectangle of colour over what is there with opacity alpha / 255 (255: as fill, 0: nothing).
  virtual void blend(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                     std::uint8_t alpha) = 0;
};

// An image as a canvas (row 0 at the top). Blending keeps the image opaque where it was.
class ImageCanvas final : public Canvas {
public:
  explicit ImageCanvas(Image& image) : image_(image) {}
  int width() const override { return image_.width; }
  int height() const override { return image_.height; }
  void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) override;
  void blend(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
             std::uint8_t alpha) override;

private:
  Image& image_;
};

// A font size: the em in pixels (fractional sizes are rasterised as such). Explicit, so that a count of
// anything else does not pass for one.
struct FontSize {
  explicit FontSize(double emPx) : px(emPx) {}
  double px;
};

// The width in pixels of `text` (UTF-8) set at `size`: the sum of its advances, kerned.
int textWidth(const std::string& text, FontSize size);
// The height in pixels of capitals and digits at `size` (DejaVu Sans: 0.73 em); drawText places the
// baseline this far below its y, so text of capitals and digits fills [y, y + textHeight). Descenders hang
// below by up to textDescent.
int textHeight(FontSize size);
int textDescent(FontSize size);

// Draws `text` (UTF-8; characters the font lacks draw as its replacement glyph) with the top of its
// capitals at y and its pen starting at x, anti-aliased, blended over the canvas.
void drawText(Canvas& canvas, int x, int y, const std::string& text, FontSize size, std::uint8_t r,
              std::uint8_t g, std::uint8_t b);
void drawText(Image& image, int x, int y, const std::string& text, FontSize size, std::uint8_t r,
              std::uint8_t g, std::uint8_t b);
// The same with a black outline `outlinePx` pixels wide around the glyphs (readable over any fabric colour).
void drawOutlinedText(Canvas& canvas, int x, int y, const std::string& text, FontSize size, int outlinePx,
                      std::uint8_t r, std::uint8_t g, std::uint8_t b);
void drawOutlinedText(Image& image, int x, int y, const std::string& text, FontSize size, int outlinePx,
                      std::uint8_t r, std::uint8_t g, std::uint8_t b);

// Fills a rectangle (clipped to the image) with an opaque colour.
void fillRect(Image& image, int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b);

} // namespace dtf::render
