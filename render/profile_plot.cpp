// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/profile_plot.h"

#include "io/model/error.h"

#include <algorithm>
#include <cairo-svg.h>
#include <cairo.h>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <pango/pangocairo.h>

namespace dtf::render {

namespace {

// Sizes in points.
constexpr double kPad = 10;                                        // around the figure
constexpr double kPanelW = 300, kPanelH = 205;                     // one panel with its axes and labels
constexpr double kLeft = 56, kRight = 14, kTop = 10, kBottom = 42; // the plot area inside a panel
constexpr double kPngScale = 3;                                    // pixels per point (216 dpi)
constexpr const char* kFont = "DejaVu Sans";

// Okabe & Ito's colour-blind-safe palette, yellow (weak on white) last.
constexpr double kColours[][3] = {{0.000, 0.447, 0.698}, {0.835, 0.369, 0.000}, {0.000, 0.620, 0.451},
                                  {0.800, 0.475, 0.655}, {0.902, 0.624, 0.000}, {0.337, 0.706, 0.914},
                                  {0.000, 0.000, 0.000}, {0.941, 0.894, 0.259}};
const double* colourOf(std::size_t i) {
  return kColours[i % (sizeof(kColours) / sizeof(kColours[0]))];
}

struct Size {
  double w = 0, h = 0;
};

// A line of text laid out by Pango in this cairo context's user space.
class TextLayout {
public:
  TextLayout(cairo_t* cr, const std::string& text, double points, bool bold = false) : cr_(cr) {
    layout_ = pango_cairo_create_layout(cr);
    PangoFontDescription* font = pango_font_description_new();
    pango_font_description_set_family(font, kFont);
    pango_font_description_set_absolute_size(font, points * PANGO_SCALE);
    if (bold) pango_font_description_set_weight(font, PANGO_WEIGHT_BOLD);
    pango_layout_set_font_description(layout_, font);
    pango_font_description_free(font);
    // The same layout in PNG and SVG: metrics not hinted to the PNG's pixel grid.
    cairo_font_options_t* options = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
    cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_NONE);
    pango_cairo_context_set_font_options(pango_layout_get_context(layout_), options);
    pango_layout_context_changed(layout_);
    cairo_font_options_destroy(options);
    pango_layout_set_text(layout_, text.c_str(), -1);
  }
  ~TextLayout() { g_object_unref(layout_); }
  TextLayout(const TextLayout&) = delete;
  TextLayout& operator=(const TextLayout&) = delete;

  Size size() const {
    PangoRectangle ink, logical;
    pango_layout_get_extents(layout_, &ink, &logical);
    return {static_cast<double>(logical.width) / PANGO_SCALE,
            static_cast<double>(logical.height) / PANGO_SCALE};
  }
  // Draws with the anchor (ax, ay) of its box (0 left/top, 1 right/bottom) at (x, y), turned by `angle`.
  void draw(double x, double y, double ax, double ay, double angle = 0) const {
    const Size s = size();
    cairo_save(cr_);
    cairo_translate(cr_, x, y);
    cairo_rotate(cr_, angle);
    cairo_move_to(cr_, -ax * s.w, -ay * s.h);
    pango_cairo_show_layout(cr_, layout_);
    cairo_restore(cr_);
  }

private:
  cairo_t* cr_;
  PangoLayout* layout_;
};

// About `target` round ticks (1, 2, 2.5 or 5 x 10^k apart) covering [lo, hi].
std::vector<double> niceTicks(double lo, double hi, int target, double& step) {
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + step * 1e-9; t += step)
    ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  return ticks;
}

std::string tickText(double v, double step) {
  int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  if (std::abs(step * std::pow(10.0, decimals) - std::round(step * std::pow(10.0, decimals))) > 1e-6)
    ++decimals;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.rfind('-', 0) == 0) s = "−" + s.substr(1); // a true minus sign
  return s;
}

std::string superscript(int n) {
  static const char* digits[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string s = n < 0 ? "⁻" : "";
  for (char c : std::to_string(std::abs(n)))
    s += digits[c - '0'];
  return s;
}

// The power of ten that brings the panel's values near 1 when they are all tiny or huge (diffusivities in
// mm^2/s): 0 otherwise.
int panelExponent(const ProfilePanel& p) {
  double peak = 0;
  for (const auto& s : p.series)
    for (const auto* v : {&s.mean, &s.low, &s.high})
      for (double x : *v)
        if (std::isfinite(x)) peak = std::max(peak, std::abs(x));
  if (!(peak > 0) || (peak >= 0.01 && peak < 1e4)) return 0;
  return static_cast<int>(std::floor(std::log10(peak)));
}

struct Frame {
  double x0, y0, x1, y1;     // plot area, points (y down)
  double xlo, xhi, ylo, yhi; // data range
  double scale;              // values are multiplied by this before plotting
  double px(double node) const { return x0 + (node - xlo) / (xhi - xlo) * (x1 - x0); }
  double py(double v) const { return y1 - (v * scale - ylo) / (yhi - ylo) * (y1 - y0); }
};

void setColour(cairo_t* cr, const double* c, double alpha = 1) {
  cairo_set_source_rgba(cr, c[0], c[1], c[2], alpha);
}

// Runs of consecutive nodes where every given array is finite.
template <typename Fn>
void forEachRun(std::size_t n, const std::vector<const std::vector<double>*>& arrays, Fn fn) {
  std::size_t k = 0;
  auto ok = [&](std::size_t i) {
    for (const auto* a : arrays)
      if (i >= a->size() || !std::isfinite((*a)[i])) return false;
    return true;
  };
  while (k < n) {
    while (k < n && !ok(k))
      ++k;
    const std::size_t b = k;
    while (k < n && ok(k))
      ++k;
    if (k > b) fn(b, k);
  }
}

void drawPanel(cairo_t* cr, const ProfilePanel& panel, const std::string& xLabel, double ox, double oy) {
  std::size_t nodes = 0;
  for (const auto& s : panel.series)
    nodes = std::max(nodes, s.mean.size());
  const int exponent = panelExponent(panel);
  Frame f{ox + kLeft,
          oy + kTop,
          ox + kPanelW - kRight,
          oy + kPanelH - kBottom,
          0,
          std::max(1.0, static_cast<double>(nodes) - 1),
          0,
          1,
          std::pow(10.0, -exponent)};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : panel.series)
    for (const auto* v : {&s.mean, &s.low, &s.high})
      for (double x : *v)
        if (std::isfinite(x)) lo = std::min(lo, x * f.scale), hi = std::max(hi, x * f.scale);
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
  const double margin = 0.06 * (hi - lo);
  f.ylo = lo - margin;
  f.yhi = hi + margin;

  // Grid and y ticks.
  double ystep = 1, tickW = 0;
  const auto yticks = niceTicks(f.ylo, f.yhi, 5, ystep);
  cairo_set_line_width(cr, 0.5);
  for (double t : yticks) {
    tickW = std::max(tickW, TextLayout(cr, tickText(t, ystep), 8.5).size().w);
    const double y = f.y1 - (t - f.ylo) / (f.yhi - f.ylo) * (f.y1 - f.y0);
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, f.x0, y);
    cairo_line_to(cr, f.x1, y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_move_to(cr, f.x0 - 3, y);
    cairo_line_to(cr, f.x0, y);
    cairo_stroke(cr);
    TextLayout(cr, tickText(t, ystep), 8.5).draw(f.x0 - 5, y, 1, 0.5);
  }
  double xstep = 1;
  for (double t : niceTicks(f.xlo, f.xhi, 5, xstep)) {
    const double x = f.px(t);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, 0.5);
    cairo_move_to(cr, x, f.y1);
    cairo_line_to(cr, x, f.y1 + 3);
    cairo_stroke(cr);
    TextLayout(cr, tickText(t, xstep), 8.5).draw(x, f.y1 + 5, 0.5, 0);
  }

  // Bands, then lines, clipped to the plot area.
  cairo_save(cr);
  cairo_rectangle(cr, f.x0, f.y0, f.x1 - f.x0, f.y1 - f.y0);
  cairo_clip(cr);
  for (std::size_t i = 0; i < panel.series.size(); ++i) {
    const auto& s = panel.series[i];
    forEachRun(s.mean.size(), {&s.low, &s.high}, [&](std::size_t b, std::size_t e) {
      cairo_move_to(cr, f.px(double(b)), f.py(s.high[b]));
      for (std::size_t k = b + 1; k < e; ++k)
        cairo_line_to(cr, f.px(double(k)), f.py(s.high[k]));
      for (std::size_t k = e; k-- > b;)
        cairo_line_to(cr, f.px(double(k)), f.py(s.low[k]));
      cairo_close_path(cr);
      setColour(cr, colourOf(i), 0.2);
      cairo_fill(cr);
    });
  }
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr, 1.6);
  for (std::size_t i = 0; i < panel.series.size(); ++i) {
    const auto& s = panel.series[i];
    forEachRun(s.mean.size(), {&s.mean}, [&](std::size_t b, std::size_t e) {
      cairo_move_to(cr, f.px(double(b)), f.py(s.mean[b]));
      for (std::size_t k = b + 1; k < e; ++k)
        cairo_line_to(cr, f.px(double(k)), f.py(s.mean[k]));
      if (e - b == 1) cairo_line_to(cr, f.px(double(b)) + 0.01, f.py(s.mean[b])); // a lone node as a dot
      setColour(cr, colourOf(i));
      cairo_stroke(cr);
    });
  }
  cairo_restore(cr);

  // Axes (left and bottom) and labels.
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  cairo_set_line_width(cr, 0.8);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_SQUARE);
  cairo_move_to(cr, f.x0, f.y0);
  cairo_line_to(cr, f.x0, f.y1);
  cairo_line_to(cr, f.x1, f.y1);
  cairo_stroke(cr);
  TextLayout(cr, xLabel, 10).draw(0.5 * (f.x0 + f.x1), oy + kPanelH - 3, 0.5, 1);
  const std::string yLabel = panel.yLabel + (exponent ? " (×10" + superscript(exponent) + ")" : "");
  TextLayout(cr, yLabel, 10)
      .draw(std::max(ox + 2, f.x0 - 12 - tickW), 0.5 * (f.y0 + f.y1), 0.5, 1, -M_PI / 2);
}

// The legend's entries laid out in rows within `width`: returns the height and draws when `draw`.
double legend(cairo_t* cr, const std::vector<ProfileSeries>& series, double x, double y, double width,
              bool draw) {
  constexpr double swatch = 18, gap = 5, spacing = 16, rowH = 16;
  double cx = x, cy = y;
  for (std::size_t i = 0; i < series.size(); ++i) {
    TextLayout label(cr, series[i].label, 9.5);
    const double w = swatch + gap + label.size().w;
    if (cx > x && cx + w > x + width) {
      cx = x;
      cy += rowH;
    }
    if (draw) {
      setColour(cr, colourOf(i), 0.2);
      cairo_rectangle(cr, cx, cy + rowH / 2 - 4, swatch, 8);
      cairo_fill(cr);
      setColour(cr, colourOf(i));
      cairo_set_line_width(cr, 1.6);
      cairo_move_to(cr, cx, cy + rowH / 2);
      cairo_line_to(cr, cx + swatch, cy + rowH / 2);
      cairo_stroke(cr);
      cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
      label.draw(cx + swatch + gap, cy + rowH / 2, 0, 0.5);
    }
    cx += w + spacing;
  }
  return series.empty() ? 0 : cy - y + rowH;
}

void drawFigure(cairo_t* cr, const ProfileFigure& fig, double width, double legendH, int columns) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  legend(cr, fig.panels.front().series, kPad + kLeft, kPad, width - 2 * kPad - kLeft, true);
  for (std::size_t p = 0; p < fig.panels.size(); ++p) {
    const double ox = kPad + static_cast<double>(p % columns) * kPanelW;
    const double oy = kPad + legendH + 6 + static_cast<double>(p / columns) * kPanelH;
    drawPanel(cr, fig.panels[p], fig.xLabel, ox, oy);
  }
}

} // namespace

bool plotFormatOf(const std::string& path, PlotFormat& format) {
  auto endsWith = [&](const char* ext) {
    const std::string e = ext;
    if (path.size() < e.size()) return false;
    for (std::size_t i = 0; i < e.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(path[path.size() - e.size() + i])) != e[i]) return false;
    return true;
  };
  if (endsWith(".png")) return format = PlotFormat::Png, true;
  if (endsWith(".svg")) return format = PlotFormat::Svg, true;
  return false;
}

void writeProfilePlot(const ProfileFigure& fig, const std::string& path, PlotFormat format,
                      const std::string& name) {
  const std::string shown = name.empty() ? path : name;
  if (fig.panels.empty()) throw InputError(shown + ": a profile plot needs at least one scalar");
  const int columns = fig.panels.size() > 1 ? 2 : 1;
  const int rows = static_cast<int>((fig.panels.size() + columns - 1) / columns);
  const double width = 2 * kPad + columns * kPanelW;
  // Measure the legend on a scratch surface (the same font options as the drawing).
  double legendH = 0;
  {
    cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
    cairo_t* cr = cairo_create(scratch);
    legendH = legend(cr, fig.panels.front().series, kPad + kLeft, kPad, width - 2 * kPad - kLeft, false);
    cairo_destroy(cr);
    cairo_surface_destroy(scratch);
  }
  const double height = 2 * kPad + legendH + 6 + rows * kPanelH;

  cairo_surface_t* surface =
      format == PlotFormat::Svg
          ? cairo_svg_surface_create(path.c_str(), width, height)
          : cairo_image_surface_create(CAIRO_FORMAT_ARGB32, static_cast<int>(std::ceil(width * kPngScale)),
                                       static_cast<int>(std::ceil(height * kPngScale)));
  if (format == PlotFormat::Svg) cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_PT);
  cairo_t* cr = cairo_create(surface);
  if (format == PlotFormat::Png) cairo_scale(cr, kPngScale, kPngScale);
  drawFigure(cr, fig, width, legendH, columns);
  cairo_status_t status = cairo_status(cr);
  cairo_destroy(cr);
  if (status == CAIRO_STATUS_SUCCESS && format == PlotFormat::Png)
    status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_finish(surface);
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw InputError(shown + ": cannot write the plot (" + cairo_status_to_string(status) + ")");
}

} // namespace dtf::render
