// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/text.h"

#include "io/model/error.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_TRUETYPE_TABLES_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <unordered_map>
#include <vector>

#ifndef DTF_FONT_FILE
#define DTF_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#endif

namespace dtf::render {

namespace {

// One rasterised glyph: its coverage (w x h, row 0 at the top), where it sits relative to the pen on the
// baseline (left, top: pixels right of and above the pen) and the pen's advance in 1/64 pixel.
struct Glyph {
  int left = 0, top = 0, w = 0, h = 0;
  long advance = 0;
  unsigned index = 0;
  std::vector<std::uint8_t> alpha;
};

// The font: one FreeType face, its glyphs cached per size (26.6 pixels) and character. FreeType's faces are
// not thread-safe, and callers draw from workers and the UI thread: every use holds `mutex`.
class Font {
public:
  static Font& instance() {
    static Font font; // a failure to load throws, and the next call tries again
    return font;
  }

  std::mutex mutex;

  // The glyph of `c` at `size26` (the em in 1/64 pixel). The reference stays valid while `mutex` is held.
  const Glyph& glyph(char32_t c, long size26) {
    const std::uint64_t key = (static_cast<std::uint64_t>(size26) << 32) | c;
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    if (cache_.size() > 8192) cache_.clear(); // many sizes (a window resized): drop them all
    setSize(size26);
    Glyph g;
    g.index = FT_Get_Char_Index(face_, c);
    // Light hinting: vertical only, so that widths follow the size smoothly and stems stay sharp.
    if (FT_Load_Glyph(face_, g.index, FT_LOAD_TARGET_LIGHT) == 0 &&
        FT_Render_Glyph(face_->glyph, FT_RENDER_MODE_NORMAL) == 0) {
      const FT_GlyphSlot s = face_->glyph;
      g.left = s->bitmap_left;
      g.top = s->bitmap_top;
      g.w = static_cast<int>(s->bitmap.width);
      g.h = static_cast<int>(s->bitmap.rows);
      g.advance = s->advance.x;
      g.alpha.resize(static_cast<std::size_t>(g.w) * g.h);
      for (int y = 0; y < g.h; ++y) {
        const unsigned char* row = s->bitmap.buffer + static_cast<std::ptrdiff_t>(y) * s->bitmap.pitch;
        std::copy(row, row + g.w, g.alpha.begin() + static_cast<std::ptrdiff_t>(y) * g.w);
      }
    }
    return cache_.emplace(key, std::move(g)).first->second;
  }

  // The kerning between two glyphs at `size26`, in 1/64 pixel.
  long kerning(unsigned left, unsigned right, long size26) {
    if (!FT_HAS_KERNING(face_) || !left || !right) return 0;
    setSize(size26);
    FT_Vector k{};
    if (FT_Get_Kerning(face_, left, right, FT_KERNING_DEFAULT, &k) != 0) return 0;
    return k.x;
  }

  double capHeightEm() const { return capHeightEm_; }
  double descentEm() const { return descentEm_; }

private:
  Font() {
    const char* env = std::getenv("DTF_FONT_FILE");
    const std::string path = env && *env ? env : DTF_FONT_FILE;
    if (FT_Init_FreeType(&library_) != 0) throw Error("FreeType failed to initialise");
    if (FT_New_Face(library_, path.c_str(), 0, &face_) != 0) {
      FT_Done_FreeType(library_);
      throw Error("cannot load the font " + path +
                  " for the figures' text (Debian: fonts-dejavu-core; another file: DTF_FONT_FILE)");
    }
    const double em = face_->units_per_EM > 0 ? face_->units_per_EM : 2048.0;
    const auto* os2 = static_cast<const TT_OS2*>(FT_Get_Sfnt_Table(face_, FT_SFNT_OS2));
    capHeightEm_ = os2 && os2->version >= 2 && os2->sCapHeight > 0 ? os2->sCapHeight / em : 0.73;
    descentEm_ = std::abs(static_cast<double>(face_->descender)) / em;
  }
  ~Font() {
    FT_Done_Face(face_);
    FT_Done_FreeType(library_);
  }
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  void setSize(long size26) {
    if (size26 == size26_) return;
    FT_Set_Char_Size(face_, 0, size26, 72, 72);
    size26_ = size26;
  }

  FT_Library library_ = nullptr;
  FT_Face face_ = nullptr;
  long size26_ = -1;
  double capHeightEm_ = 0.73, descentEm_ = 0.24;
  std::unordered_map<std::uint64_t, Glyph> cache_;
};

long size26(FontSize size) {
  return std::max(64L, std::lround(size.px * 64.0)); // at least one pixel
}

// The next code point of UTF-8 `s` from `i` (advanced past it); U+FFFD for a malformed sequence.
char32_t nextCodePoint(const std::string& s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i++);
  if (c < 0x80) return c;
  int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : -1;
  if (extra < 0) return 0xFFFD;
  char32_t cp = c & (0x3F >> extra);
  for (; extra > 0; --extra) {
    if (i >= s.size() || (byte(i) & 0xC0) != 0x80) return 0xFFFD;
    cp = (cp << 6) | (byte(i++) & 0x3F);
  }
  return cp;
}

// Calls f(glyph, x, baselineY) for each glyph of `text` with its pen at x (whole pixels), the font locked.
template <class F>
void layOut(const std::string& text, FontSize size, F&& f) {
  Font& font = Font::instance();
  const long s26 = size26(size);
  std::lock_guard lock(font.mutex);
  long pen = 0; // 26.6
  unsigned previous = 0;
  for (std::size_t i = 0; i < text.size();) {
    const Glyph& g = font.glyph(nextCodePoint(text, i), s26);
    pen += font.kerning(previous, g.index, s26);
    f(g, static_cast<int>((pen + 32) >> 6));
    pen += g.advance;
    previous = g.index;
  }
}

// The coverage of `text` in a buffer with `pad` free pixels around its box; the box's origin is the top of
// the capitals at the pen's start, less the pad (the buffer is reused across calls: no allocation once it is
// large enough).
struct Coverage {
  int x0 = 0, y0 = 0, w = 0, h = 0; // relative to (pen x, top of capitals)
  std::vector<std::uint8_t> alpha;
  std::uint8_t at(int x, int y) const { return alpha[static_cast<std::size_t>(y) * w + x]; }
};

void rasterise(const std::string& text, FontSize size, int pad, Coverage& out) {
  const int cap = textHeight(size);
  int minX = 0, maxX = 0, minY = 0, maxY = 0;
  bool any = false;
  layOut(text, size, [&](const Glyph& g, int x) {
    if (!g.w || !g.h) return;
    const int gx = x + g.left, gy = cap - g.top;
    minX = any ? std::min(minX, gx) : gx;
    minY = any ? std::min(minY, gy) : gy;
    maxX = any ? std::max(maxX, gx + g.w) : gx + g.w;
    maxY = any ? std::max(maxY, gy + g.h) : gy + g.h;
    any = true;
  });
  if (!any) {
    out.w = out.h = 0;
    return;
  }
  out.x0 = minX - pad;
  out.y0 = minY - pad;
  out.w = maxX - minX + 2 * pad;
  out.h = maxY - minY + 2 * pad;
  out.alpha.assign(static_cast<std::size_t>(out.w) * out.h, 0);
  layOut(text, size, [&](const Glyph& g, int x) {
    const int gx = x + g.left - out.x0, gy = cap - g.top - out.y0;
    for (int y = 0; y < g.h; ++y)
      for (int i = 0; i < g.w; ++i) {
        std::uint8_t& d = out.alpha[static_cast<std::size_t>(gy + y) * out.w + gx + i];
        d = std::max(d, g.alpha[static_cast<std::size_t>(y) * g.w + i]); // overlapping glyphs: the larger
      }
  });
}

// Blends a coverage buffer onto the canvas at (x, y) + its origin, one rectangle per run of equal coverage.
void blendCoverage(Canvas& canvas, int x, int y, const Coverage& c, std::uint8_t r, std::uint8_t g,
                   std::uint8_t b) {
  for (int row = 0; row < c.h; ++row) {
    const int py = y + c.y0 + row;
    if (py < 0 || py >= canvas.height()) continue;
    for (int i = 0; i < c.w;) {
      const std::uint8_t a = c.at(i, row);
      int end = i + 1;
      while (end < c.w && c.at(end, row) == a) ++end;
      if (a) canvas.blend(x + c.x0 + i, py, end - i, 1, r, g, b, a);
      i = end;
    }
  }
}

} // namespace

void ImageCanvas::fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  fillRect(image_, x, y, w, h, r, g, b);
}

void ImageCanvas::blend(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                        std::uint8_t alpha) {
  if (alpha == 255) return fillRect(image_, x, y, w, h, r, g, b);
  if (alpha == 0) return;
  const int a = alpha, keep = 255 - alpha;
  const auto mix = [&](std::uint8_t under, std::uint8_t over) {
    return static_cast<std::uint8_t>((under * keep + over * a + 127) / 255);
  };
  for (int py = std::max(y, 0); py < std::min(y + h, image_.height); ++py)
    for (int px = std::max(x, 0); px < std::min(x + w, image_.width); ++px) {
      std::uint8_t* p = image_.pixel(px, py);
      p[0] = mix(p[0], r);
      p[1] = mix(p[1], g);
      p[2] = mix(p[2], b);
      p[3] = static_cast<std::uint8_t>(a + (p[3] * keep + 127) / 255);
    }
}

void fillRect(Image& image, int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  for (int py = std::max(y, 0); py < std::min(y + h, image.height); ++py)
    for (int px = std::max(x, 0); px < std::min(x + w, image.width); ++px) {
      std::uint8_t* p = image.pixel(px, py);
      p[0] = r;
      p[1] = g;
      p[2] = b;
      p[3] = 255;
    }
}

int textWidth(const std::string& text, FontSize size) {
  Font& font = Font::instance();
  const long s26 = size26(size);
  std::lock_guard lock(font.mutex);
  long pen = 0;
  unsigned previous = 0;
  for (std::size_t i = 0; i < text.size();) {
    const Glyph& g = font.glyph(nextCodePoint(text, i), s26);
    pen += font.kerning(previous, g.index, s26) + g.advance;
    previous = g.index;
  }
  return static_cast<int>((pen + 32) >> 6);
}

int textHeight(FontSize size) {
  return static_cast<int>(std::lround(Font::instance().capHeightEm() * std::max(1.0, size.px)));
}

int textDescent(FontSize size) {
  return static_cast<int>(std::ceil(Font::instance().descentEm() * std::max(1.0, size.px)));
}

void drawText(Canvas& canvas, int x, int y, const std::string& text, FontSize size, std::uint8_t r,
              std::uint8_t g, std::uint8_t b) {
  thread_local Coverage coverage;
  rasterise(text, size, 0, coverage);
  blendCoverage(canvas, x, y, coverage, r, g, b);
}

void drawText(Image& image, int x, int y, const std::string& text, FontSize size, std::uint8_t r,
              std::uint8_t g, std::uint8_t b) {
  ImageCanvas canvas(image);
  drawText(canvas, x, y, text, size, r, g, b);
}

void drawOutlinedText(Canvas& canvas, int x, int y, const std::string& text, FontSize size, int outlinePx,
                      std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  thread_local Coverage coverage, outline;
  const int o = std::max(0, outlinePx);
  rasterise(text, size, o, coverage);
  if (o > 0 && coverage.w > 0) {
    // The outline: the coverage dilated by a disc of radius o (the largest coverage within it).
    outline.x0 = coverage.x0;
    outline.y0 = coverage.y0;
    outline.w = coverage.w;
    outline.h = coverage.h;
    outline.alpha.assign(coverage.alpha.size(), 0);
    for (int yy = 0; yy < coverage.h; ++yy)
      for (int xx = 0; xx < coverage.w; ++xx) {
        std::uint8_t m = 0;
        for (int dy = -o; dy <= o; ++dy)
          for (int dx = -o; dx <= o; ++dx) {
            const int sx = xx + dx, sy = yy + dy;
            if (dx * dx + dy * dy > o * o + o || sx < 0 || sy < 0 || sx >= coverage.w || sy >= coverage.h)
              continue;
            m = std::max(m, coverage.at(sx, sy));
          }
        outline.alpha[static_cast<std::size_t>(yy) * outline.w + xx] = m;
      }
    blendCoverage(canvas, x, y, outline, 0, 0, 0);
  }
  blendCoverage(canvas, x, y, coverage, r, g, b);
}

void drawOutlinedText(Image& image, int x, int y, const std::string& text, FontSize size, int outlinePx,
                      std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  ImageCanvas canvas(image);
  drawOutlinedText(canvas, x, y, text, size, outlinePx, r, g, b);
}

} // namespace dtf::render
