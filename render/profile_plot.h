// SPDX-License-Identifier: GPL-3.0-or-later
// The figure of tract profiles (`dtfabric profile --plot`): a panel per scalar, each bundle a line with its
// confidence band over the node axis, the axis labelled with where the bundles start and end, one legend for
// the figure. Drawn with Cairo, text laid out by Pango in DejaVu Sans, into PNG or SVG by the same code; no
// GL. Plain data in, so any front end can draw it (the command line fills it from ui/session's profiles).
#pragma once

#include <string>
#include <vector>

namespace dtf::render {

struct ProfileSeries {
  std::string label;                   // the legend's text (a bundle's name)
  std::vector<double> mean, low, high; // per node; NaN leaves a gap
};

struct ProfilePanel {
  std::string yLabel; // the scalar's name, e.g. "FA"; the panel adds the power of ten it scales values by
  std::vector<ProfileSeries> series;
};

struct ProfileFigure {
  std::vector<ProfilePanel> panels; // every panel shows the same bundles in the same order
  std::string xLabel;               // e.g. "node (inferior → superior)"
};

enum class PlotFormat { Png, Svg };

// The format a file name asks for: .png or .svg (case-insensitive); false for anything else.
bool plotFormatOf(const std::string& path, PlotFormat& format);

// Draws the figure into `path` (written directly: callers wanting an atomic file pass a temporary path and
// the target as `name`, which errors name instead). PNG at 3 pixels per point (216 dpi), SVG in points.
// Throws InputError when Cairo cannot write the file, and for a figure without panels.
void writeProfilePlot(const ProfileFigure& figure, const std::string& path, PlotFormat format,
                      const std::string& name = "");

} // namespace dtf::render
