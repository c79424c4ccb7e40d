// SPDX-License-Identifier: GPL-3.0-or-later
// The tracking-parameter table: every default inside its range, every slider inside it, parsing and the
// range errors, and validate() refusing each parameter just outside its range.
#include "io/model/error.h"
#include "surfaces/tracking/tracking_parameters.h"

#include <cmath>
#include <gtest/gtest.h>
#include <set>
#include <string>

using namespace dtf;
using namespace dtf::surfaces;

TEST(TrackingParameters, DefaultsAndSlidersLieInTheirRanges) {
  const TrackingParams d;
  std::set<std::string> names;
  for (const auto& p : trackingParameters()) {
    SCOPED_TRACE(p.name);
    EXPECT_TRUE(names.insert(p.name).second) << "declared twice";
    EXPECT_TRUE(p.range.contains(p.get(d)));
    EXPECT_LT(p.slider.lo, p.slider.hi);
    EXPECT_TRUE(p.range.contains(p.slider.lo));
    EXPECT_TRUE(p.range.contains(p.slider.hi));
    EXPECT_TRUE(p.sliderLabel && *p.sliderLabel);
    EXPECT_EQ(findTrackingParameter(p.name), &p);
  }
  EXPECT_EQ(names, (std::set<std::string>{"fa-stop", "angle", "step", "min-length", "max-length"}));
  EXPECT_EQ(findTrackingParameter("nope"), nullptr);
  EXPECT_EQ(findTrackingParameter("fa-stop")->pythonName(), "fa_stop");
}

TEST(TrackingParameters, SetAndGetReachTheirField) {
  TrackingParams p;
  findTrackingParameter("angle")->set(p, 35);
  findTrackingParameter("step")->set(p, 0.5);
  findTrackingParameter("fa-stop")->set(p, 0.2);
  findTrackingParameter("min-length")->set(p, 12);
  findTrackingParameter("max-length")->set(p, 80);
  EXPECT_DOUBLE_EQ(p.maxAngleDeg, 35);
  EXPECT_DOUBLE_EQ(p.stepMm, 0.5);
  EXPECT_DOUBLE_EQ(p.faStop, 0.2);
  EXPECT_DOUBLE_EQ(p.minLengthMm, 12);
  EXPECT_DOUBLE_EQ(p.maxLengthMm, 80);
  EXPECT_NO_THROW(validate(p));
}

TEST(TrackingParameters, ParseRefusesTextAndValuesOutsideTheRange) {
  const TrackingParameter& angle = *findTrackingParameter("angle");
  EXPECT_DOUBLE_EQ(angle.parse("45"), 45);
  EXPECT_DOUBLE_EQ(angle.parse("180"), 180);
  try {
    angle.parse("200");
    FAIL() << "200 degrees accepted";
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "angle must lie in (0, 180] degrees, got 200");
  }
  EXPECT_THROW(angle.parse("0"), UsageError);
  EXPECT_THROW(angle.parse("4x"), UsageError);
  EXPECT_THROW(angle.parse(""), UsageError);
  EXPECT_THROW(angle.parse("nan"), UsageError);
  EXPECT_THROW(findTrackingParameter("fa-stop")->parse("1"), UsageError) << "[0, 1): 1 is outside";
  EXPECT_DOUBLE_EQ(findTrackingParameter("fa-stop")->parse("0"), 0);
}

// validate() refuses each parameter just outside each finite bound of its range, and accepts the bound
// itself where the range is closed there.
TEST(TrackingParameters, ValidateFollowsTheTable) {
  for (const auto& p : trackingParameters()) {
    SCOPED_TRACE(p.name);
    for (const double bound : {p.range.lo, p.range.hi}) {
      if (!std::isfinite(bound)) continue;
      const bool lower = bound == p.range.lo;
      const bool open = lower ? p.range.loOpen : p.range.hiOpen;
      TrackingParams t;
      t.minLengthMm = 0; // so the length bounds test their own parameter
      t.maxLengthMm = 100;
      p.set(t, bound + (lower ? -1e-9 : 1e-9) * std::max(1.0, std::abs(bound)));
      EXPECT_THROW(validate(t), UsageError);
      p.set(t, bound);
      if (open || (std::string(p.name) == "max-length" || std::string(p.name) == "min-length")) continue;
      EXPECT_NO_THROW(validate(t)) << bound;
    }
  }
  TrackingParams crossed;
  crossed.minLengthMm = 50;
  crossed.maxLengthMm = 20;
  try {
    validate(crossed);
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "min-length 50 mm exceeds max-length 20 mm");
  }
}
