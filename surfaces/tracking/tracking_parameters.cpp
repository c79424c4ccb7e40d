// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/tracking/tracking_parameters.h"

#include "io/model/error.h"

#include <algorithm>
#include <cstdlib>

namespace dtf::surfaces {

namespace {

#define DTF_PARAM(field)                                                                                     \
  [](const TrackingParams& p) { return static_cast<double>(p.field); },                                      \
      [](TrackingParams& p, double v) { p.field = v; }

} // namespace

const std::vector<TrackingParameter>& trackingParameters() {
  static const std::vector<TrackingParameter> table = {
      {"fa-stop", "F", "stop where FA < F; seeds below F are rejected", "", Range{0, 1, false, true},
       Range::closed(0, 0.6), "FA stop", "%.2f", DTF_PARAM(faStop)},
      {"angle", "DEG", "largest turn between successive steps (per step, as in MRtrix)", "degrees",
       Range{0, 180, true, false}, Range::closed(5, 90), "angle (deg/step)", "%.0f", DTF_PARAM(maxAngleDeg)},
      {"step", "MM", "step length", "mm", Range{0, 100, true, false}, Range::closed(0.1, 3), "step (mm)",
       "%.2f", DTF_PARAM(stepMm)},
      {"min-length", "MM", "discard shorter streamlines", "mm", Range::closed(0, 100000),
       Range::closed(0, 200), "min length (mm)", "%.0f", DTF_PARAM(minLengthMm)},
      {"max-length", "MM", "stop at this length", "mm", Range{0, 100000, true, false}, Range::closed(10, 500),
       "max length (mm)", "%.0f", DTF_PARAM(maxLengthMm)},
  };
  return table;
}

#undef DTF_PARAM

const TrackingParameter* findTrackingParameter(const std::string& name) {
  for (const auto& p : trackingParameters())
    if (name == p.name) return &p;
  return nullptr;
}

std::string TrackingParameter::pythonName() const {
  std::string s = name;
  std::replace(s.begin(), s.end(), '-', '_');
  return s;
}

void TrackingParameter::check(double v) const {
  if (!range.contains(v))
    throw UsageError(std::string(name) + " must lie in " + range.text() + (*unit ? " " : "") + unit +
                     ", got " + shortestNumber(v));
}

double TrackingParameter::parse(const std::string& text) const {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw UsageError(std::string(name) + " takes a number, got '" + text + "'");
  check(v);
  return v;
}

} // namespace dtf::surfaces
