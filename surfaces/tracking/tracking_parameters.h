// SPDX-License-Identifier: GPL-3.0-or-later
// The tracking parameters, each declared once: its name (the flag `--NAME` of `dtfabric track`, the key of
// the viewer script's `track NAME=VALUE`, the Python keyword with '-' as '_'), help, the range every front
// end accepts, the Tracking panel's slider and the TrackingParams field it sets. `track`, the script
// parser, the panel and the Python module read this table; the defaults are TrackingParams' own.
#pragma once

#include "io/model/range.h"
#include "surfaces/tracking/tracking.h"

#include <string>
#include <vector>

namespace dtf::surfaces {

struct TrackingParameter {
  const char* name;    // "fa-stop"
  const char* metavar; // "F"
  const char* help;    // one line, without default and range
  const char* unit;    // of the range ("mm", "degrees"), "" none
  Range range;         // accepted by the CLI, scripts, Python and the panel
  Range slider;        // the panel's slider (a narrower range; values typed outside it stay in `range`)
  const char* sliderLabel;
  const char* sliderFormat;
  double (*get)(const TrackingParams&);
  void (*set)(TrackingParams&, double);

  std::string pythonName() const; // "fa_stop"
  // Parses and checks `text`; throws UsageError "NAME must lie in RANGE UNIT, got TEXT".
  double parse(const std::string& text) const;
  // Throws UsageError when `v` lies outside the range.
  void check(double v) const;
};

// The numeric parameters in the order help lists them.
const std::vector<TrackingParameter>& trackingParameters();
// The parameter named `name`, nullptr when none.
const TrackingParameter* findTrackingParameter(const std::string& name);

// The integrator switch beside the table: `--rk4`/`--euler` flags, script words `rk4`/`euler`, Python rk4=.
inline constexpr const char* kRk4Help = "fourth-order Runge-Kutta integrator (the default)";
inline constexpr const char* kEulerHelp = "Euler integrator (as MRtrix Tensor_Det)";

} // namespace dtf::surfaces
