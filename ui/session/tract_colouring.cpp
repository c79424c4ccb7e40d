// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/tract_colouring.h"

#include "io/model/error.h"
#include "io/model/log.h"
#include "render/tract_renderer.h"
#include "surfaces/analyses/tract_profile.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <tuple>

namespace dtf::session {

namespace {
// A per-streamline marker of the ROI selection, carried through the group choice's subset and removed by
// dimUnselected.
constexpr const char* kRoiMarker = "\x01roi selected";
constexpr float kDimGrey = 0.3f; // the colour of the streamlines the selection leaves out (lit)

void markRoiSelection(Polylines& lines, const std::vector<std::uint32_t>& selected) {
  TractValues m;
  m.name = kRoiMarker;
  m.values.assign(lines.lineCount(), 0.0f);
  for (std::uint32_t i : selected)
    if (i < m.values.size()) m.values[i] = 1.0f;
  lines.perLine.push_back(std::move(m));
}

// Adds the per-point node (render::kTractDisplayNode) of `lines` as the profile orients the streamlines
// `which` of them (all when null); replaces an earlier one.
void addDisplayNodes(Polylines& lines, const std::vector<std::uint32_t>* which) {
  std::erase_if(lines.perPoint, [](const TractValues& v) { return v.name == render::kTractDisplayNode; });
  if (lines.points.empty()) return;
  lines.perPoint.push_back(
      {render::kTractDisplayNode, 1, surfaces::nodePerPoint(lines, which, surfaces::ProfileOptions{})});
}

// Gives the marked-out streamlines the dim grey as display colour (alpha 1: lit grey); the others keep
// theirs (DEC where none was given).
void dimUnselected(Polylines& lines) {
  auto m = std::find_if(lines.perLine.begin(), lines.perLine.end(),
                        [](const TractValues& v) { return v.name == kRoiMarker; });
  if (m == lines.perLine.end()) return;
  auto c = std::find_if(lines.perPoint.begin(), lines.perPoint.end(),
                        [](const TractValues& v) { return v.name == render::kTractDisplayColours; });
  if (c == lines.perPoint.end()) {
    lines.perPoint.push_back({render::kTractDisplayColours, 4, std::vector<float>(lines.points.size() * 4, 0.0f)});
    c = std::prev(lines.perPoint.end());
    m = std::find_if(lines.perLine.begin(), lines.perLine.end(),
                     [](const TractValues& v) { return v.name == kRoiMarker; });
  }
  for (std::size_t i = 0; i < lines.lineCount(); ++i) {
    if (m->values[i] != 0.0f) continue;
    for (std::uint32_t k = lines.offsets[i]; k < lines.offsets[i + 1]; ++k) {
      float* rgba = &c->values[static_cast<std::size_t>(k) * 4];
      rgba[0] = rgba[1] = rgba[2] = kDimGrey;
      rgba[3] = 1.0f;
    }
  }
  lines.perLine.erase(m);
}

std::string namesOf(const Polylines& l, bool groups) {
  std::string s;
  auto add = [&](const std::string& n) { s += (s.empty() ? "'" : ", '") + n + "'"; };
  if (groups)
    for (const auto& g : l.groups)
      add(g.name);
  else {
    for (const auto& d : l.perPoint)
      add(d.name);
    for (const auto& d : l.perLine)
      add(d.name);
  }
  return s.empty() ? "none" : s;
}
} // namespace

void shadowReservedName(const Polylines& lines, const std::string& name, const std::string& path) {
  const auto shadows = [&](const std::vector<TractValues>& d) {
    return std::any_of(d.begin(), d.end(), [&](const TractValues& x) { return x.name == name; });
  };
  if (shadows(lines.perPoint) || shadows(lines.perLine))
    logWarning(path + ": its data named '" + name + "' is not shown: '" + name + "' colours by the " +
               (name == kNodeColouring ? "profile's node index" : "profile's value"));
}

std::pair<double, double> parseTractRange(const std::string& text) {
  double lo = 0, hi = 0;
  char comma = 0, extra = 0;
  std::istringstream ss(text);
  ss >> lo >> comma >> hi;
  if (ss.fail() || comma != ',' || (ss >> extra) || !std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
    throw UsageError("--tracts-range must be LO,HI with LO < HI (got '" + text + "')");
  return {lo, hi};
}

void checkTractColouring(const Polylines& lines, const TractColouring& c, const std::string& path) {
  for (const auto& name : c.groups)
    if (std::none_of(lines.groups.begin(), lines.groups.end(), [&](const TractGroup& x) { return x.name == name; }))
      throw InputError(path + ": no group '" + name + "' (groups: " + namesOf(lines, true) + ")");
  if (c.value.empty()) return;
  if (c.value == kProfileColouring)
    throw UsageError(
        "'" + std::string(kProfileColouring) +
        "' colours by the viewer's profile (its Profile panel); here colour by 'node' or by data");
  const auto named = [&](const std::vector<TractValues>& d) {
    return std::any_of(d.begin(), d.end(), [&](const TractValues& x) { return x.name == c.value; });
  };
  if (c.value != kNodeColouring && !named(lines.perPoint) && !named(lines.perLine) && !lines.points.empty())
    throw InputError(path + ": no per-point or per-streamline data '" + c.value +
                     "' (data: " + namesOf(lines, false) + ")");
}

TractColouringApplied applyTractColouring(Polylines& lines, const TractColouring& c,
                                          const std::string& path) {
  TractColouringApplied out;
  checkTractColouring(lines, c, path);
  if (!c.groups.empty()) {
    std::vector<char> keep(lines.lineCount(), 0);
    for (const auto& name : c.groups) {
      auto g = std::find_if(lines.groups.begin(), lines.groups.end(),
                            [&](const TractGroup& x) { return x.name == name; });
      for (std::uint32_t l : g->lines)
        if (l < keep.size()) keep[l] = 1;
    }
    std::vector<std::uint32_t> chosen;
    for (std::uint32_t l = 0; l < keep.size(); ++l)
      if (keep[l]) chosen.push_back(l);
    lines = lines.subset(chosen);
  }
  if (c.value.empty()) return out;
  const bool node = c.value == kNodeColouring;
  if (node) shadowReservedName(lines, kNodeColouring, path);
  const std::vector<float> v = node ? surfaces::nodePerPoint(lines, nullptr, surfaces::ProfileOptions{})
                                    : lines.valuesPerPoint(c.value);
  if (v.empty() && !lines.points.empty())
    throw InputError(path + ": no per-point or per-streamline data '" + c.value +
                     "' (data: " + namesOf(lines, false) + ")");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float x : v)
    if (std::isfinite(x)) lo = std::min(lo, double(x)), hi = std::max(hi, double(x));
  if (node) lo = 0, hi = surfaces::ProfileOptions{}.nodes - 1;
  if (c.range) std::tie(lo, hi) = *c.range;
  if (!(lo <= hi)) lo = hi = 0; // no finite value
  TractValues colours{render::kTractDisplayColours, 4, std::vector<float>(4 * v.size())};
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) continue; // alpha 0: DEC where the value is missing
    const float t = hi > lo ? static_cast<float>((v[i] - lo) / (hi - lo)) : 0.5f;
    const glm::vec3 rgb = render::tractValueColour(t);
    colours.values[4 * i] = rgb.x, colours.values[4 * i + 1] = rgb.y, colours.values[4 * i + 2] = rgb.z;
    colours.values[4 * i + 3] = 1.0f;
  }
  lines.perPoint.push_back(std::move(colours));
  out.coloured = true;
  out.lo = lo;
  out.hi = hi;
  char buf[320];
  if (node)
    std::snprintf(buf, sizeof buf,
                  "tracts coloured by the profile's node index along the oriented bundle (as `dtfabric "
                  "profile` orients it, %d nodes) from %g (bottom of the bar) to %g (top), viridis",
                  surfaces::ProfileOptions{}.nodes, lo, hi);
  else
    std::snprintf(buf, sizeof buf, "tracts coloured by '%s' from %g (bottom of the bar) to %g (top), viridis",
                  c.value.c_str(), lo, hi);
  out.summary = buf;
  return out;
}

ShownTracts prepareShownTracts(const TractChoice& c) {
  ShownTracts out;
  if (!c.copies()) {
    out.lines = c.base;
    return out;
  }
  Polylines lines = *c.base;
  if (c.byProfile) shadowReservedName(lines, kProfileColouring, c.path);
  // With regions the profile measures the selection: its indices into every streamline when the others are
  // dimmed, the subset itself when they are hidden. Without, the tracts on screen after the group choice.
  if (c.nodes && c.roi) addDisplayNodes(lines, c.dim ? c.roiLines.get() : nullptr);
  if (c.dim) markRoiSelection(lines, *c.roiLines);
  if (c.noGroups) lines = lines.subset(std::vector<std::uint32_t>{});
  if (!c.colouring.value.empty() || !c.colouring.groups.empty())
    out.applied = applyTractColouring(lines, c.colouring, c.path);
  if (c.nodes && !c.roi) addDisplayNodes(lines, nullptr);
  if (c.dim) dimUnselected(lines);
  out.lines = std::make_shared<const Polylines>(std::move(lines));
  return out;
}

} // namespace dtf::session
