// The viewer's tracking request as the tracking library's options: shared by the tract worker and the
// script parser (which validates `track` lines when the script is read), header-only so the script parser
// builds without the worker.
#pragma once

#include "surfaces/tracking/tracking.h"
#include "ui/session/actions.h"

namespace dtf::session {

// The tracking options of a request (validated by surfaces::validate when tracking starts).
inline surfaces::TrackingOptions trackingOptions(const ViewerTrackRequest& r) {
  surfaces::TrackingOptions o;
  o.stepMm = r.stepMm;
  o.faStop = r.faStop;
  o.maxAngleDeg = r.angleDeg;
  o.minLengthMm = r.minLengthMm;
  o.maxLengthMm = r.maxLengthMm;
  o.rk4 = r.rk4;
  return o;
}

} // namespace dtf::session
