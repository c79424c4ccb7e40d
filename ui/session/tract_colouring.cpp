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

TractColouringApplied applyTractColouring(Polylines& lines, const TractColouring& c,
                                          const std::string& path) {
  TractColouringApplied out;
  if (!c.groups.empty()) {
    std::vector<char> keep(lines.lineCount(), 0);
    for (const auto& name : c.groups) {
      auto g = std::find_if(lines.groups.begin(), lines.groups.end(),
                            [&](const TractGroup& x) { return x.name == name; });
      if (g == lines.groups.end())
        throw InputError(path + ": no group '" + name + "' (groups: " + namesOf(lines, true) + ")");
      for (std::uint32_t l : g->lines)
        if (l < keep.size()) keep[l] = 1;
    }
    std::vector<std::uint32_t> chosen;
    for (std::uint32_t l = 0; l < keep.size(); ++l)
      if (keep[l]) chosen.push_back(l);
    lines = lines.subset(chosen);
  }
  if (c.value.empty()) return out;
  if (c.value == kProfileColouring)
    throw UsageError(
        "'" + std::string(kProfileColouring) +
        "' colours by the viewer's profile (its Profile panel); here colour by 'node' or by data");
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

} // namespace dtf::session
