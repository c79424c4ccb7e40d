// SPDX-License-Identifier: GPL-3.0-or-later
// Tract agreement against a fibre set: each tract point is measured against the nearest fibre population in
// the surface. Closed-form angles, the threshold, and the crossing phantom, where tracts along either bundle
// agree with the fibre set but not with the tensor's average direction inside the crossing.
#include "io/model/error.h"
#include "io/phantoms.h"
#include "surfaces/analyses/agreement.h"
#include "surfaces/slices.h"

#include <cmath>
#include <gtest/gtest.h>

using dtf::Fibre;
using dtf::Polylines;

namespace {
const double kPi = 3.14159265358979323846;

glm::dvec3 inPlane(double azimuthDeg) {
  return {std::cos(azimuthDeg * kPi / 180), std::sin(azimuthDeg * kPi / 180), 0};
}
Fibre fibre(const glm::dvec3& d, float amplitude) {
  return {glm::vec3(d), amplitude};
}

// Straight polyline through (0, 0, z) along d, points every 0.5 mm for |s| <= half.
void addLine(Polylines& l, const glm::dvec3& d, double half, double z) {
  if (l.offsets.empty()) l.offsets.push_back(0);
  for (double s = -half; s <= half + 1e-9; s += 0.5)
    l.points.emplace_back(glm::dvec3(s * d.x, s * d.y, z));
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
}

dtf::io::PhantomOptions crossingOptions(double crossingDeg, int size, bool las) {
  dtf::io::PhantomOptions o;
  o.size = size;
  o.crossingDeg = crossingDeg;
  o.las = las;
  return o;
}
} // namespace

// Two in-surface populations at -30 and +30 degrees: a tangent at azimuth a is min(|a + 30|, |a - 30|)
// (folded into 0..90, directions have no sign) from the nearest; the sign of a fibre does not matter.
TEST(FibreAgreement, NearestPopulationAngleClosedForm) {
  const glm::dvec3 n(0, 0, 1);
  const std::vector<Fibre> two = {fibre(inPlane(-30), 0.5f), fibre(-inPlane(30), 0.4f)};
  for (double a : {-80.0, -30.0, -10.0, 0.0, 20.0, 45.0, 90.0, 150.0}) {
    double expected = 180;
    for (double f : {-30.0, 30.0}) {
      double d = std::fmod(std::abs(a - f), 180.0);
      expected = std::min(expected, std::min(d, 180.0 - d));
    }
    double angle = -1;
    ASSERT_TRUE(dtf::surfaces::nearestPopulationAngle(two, n, inPlane(a), 0.25, angle)) << a;
    EXPECT_NEAR(angle, expected, 1e-6) << a;
  }
  // A population along the normal has no in-surface direction; an absent one (amplitude 0) is ignored.
  double angle = -1;
  EXPECT_FALSE(dtf::surfaces::nearestPopulationAngle({fibre(n, 1.0f), fibre(inPlane(0), 0.0f)}, n, inPlane(0),
                                                     0.25, angle));
  // Out of the plane by 60 degrees the projection still counts (|P d| = 0.5 >= 0.25) and points along x.
  const glm::dvec3 tilted(std::cos(kPi / 3), 0, std::sin(kPi / 3));
  ASSERT_TRUE(dtf::surfaces::nearestPopulationAngle({fibre(tilted, 1.0f)}, n, inPlane(10), 0.25, angle));
  EXPECT_NEAR(angle, 10.0, 1e-6);
}

// A weak population below the threshold is not a candidate.
TEST(FibreAgreement, ThresholdDropsWeakPopulations) {
  dtf::FibreSet set = dtf::makeFibreSet(dtf::Grid::fromAffine({16, 16, 8}, glm::dmat4(1.0)), 2);
  for (std::size_t v = 0; v < set.grid.voxelCount(); ++v) {
    set.fibres[2 * v] = fibre(inPlane(0), 1.0f);
    set.fibres[2 * v + 1] = fibre(inPlane(90), 0.1f);
  }
  const dtf::Mesh slice = dtf::surfaces::makeSlice(set.grid, dtf::surfaces::SliceAxis::Axial, 4);
  Polylines alongY;
  alongY.offsets = {0};
  for (double y = 3; y <= 12; y += 0.5)
    alongY.points.emplace_back(8.0f, static_cast<float>(y), 4.0f);
  alongY.offsets.push_back(static_cast<std::uint32_t>(alongY.points.size()));
  dtf::surfaces::AgreementOptions ao;
  ao.fibreThreshold = 0.15f; // 0.1 < 0.15: only the x population is left
  const auto strict = dtf::surfaces::tractSurfaceAgreement(alongY, slice, set, ao);
  ASSERT_EQ(strict.anglesDeg.size(), alongY.points.size());
  EXPECT_NEAR(strict.medianDeg, 90.0, 1e-3);
  ao.fibreThreshold = 0.05f;
  const auto loose = dtf::surfaces::tractSurfaceAgreement(alongY, slice, set, ao);
  ASSERT_EQ(loose.anglesDeg.size(), alongY.points.size());
  EXPECT_NEAR(loose.medianDeg, 0.0, 1e-3);
  ao.fibreThreshold = 1.5f;
  EXPECT_THROW(dtf::surfaces::tractSurfaceAgreement(alongY, slice, set, ao), dtf::UsageError);
}

// The crossing phantom at 60 degrees (bundles at -30 and +30 degrees from x, summed in the overlap), RAS and
// LAS grids: tracts along each bundle's centre line agree with the fibre set everywhere (the nearest
// population is the tract's own bundle), while inside the overlap the tensor's principal direction is the
// bisector, 30 degrees from both.
TEST(FibreAgreement, CrossingPhantomAgreesWithEitherBundle) {
  const int size = 64;
  for (bool las : {false, true}) {
    const auto o = crossingOptions(60, size, las);
    const dtf::FibreSet fibres = dtf::io::makeFibrePhantom("crossing", o);
    const dtf::TensorField tensors = dtf::io::makePhantom("crossing", o).tensors;
    const dtf::Mesh slice = dtf::surfaces::makeSlice(tensors.grid, dtf::surfaces::SliceAxis::Axial, size / 2);
    const double z = tensors.grid.toWorld(glm::dvec3(0, 0, size / 2)).z;
    Polylines tracts;
    addLine(tracts, inPlane(-30), 26, z);
    addLine(tracts, inPlane(30), 26, z);
    const auto withFibres = dtf::surfaces::tractSurfaceAgreement(tracts, slice, fibres);
    const auto withTensors = dtf::surfaces::tractSurfaceAgreement(tracts, slice, tensors);
    ASSERT_EQ(withFibres.anglesDeg.size(), tracts.points.size()) << las;
    ASSERT_EQ(withTensors.anglesDeg.size(), tracts.points.size()) << las;
    const double halfWidth = 0.12 * (size - 1), overlapEdge = halfWidth / std::sin(60 * kPi / 180);
    int inside = 0;
    for (std::size_t i = 0; i < tracts.points.size(); ++i) {
      const double s = glm::length(glm::dvec2(tracts.points[i].x, tracts.points[i].y));
      EXPECT_LT(withFibres.anglesDeg[i], 3.0) << "las " << las << ", s = " << s;
      if (s < overlapEdge - 1.5) {
        EXPECT_NEAR(withTensors.anglesDeg[i], 30.0, 1.0) << "las " << las << ", s = " << s;
        ++inside;
      }
    }
    EXPECT_GT(inside, 20) << las;
    EXPECT_GT(withFibres.fracBelow15, 0.999) << las;
    EXPECT_LT(withTensors.fracBelow15, 0.8) << las;
    EXPECT_EQ(withFibres.histogram[0], tracts.points.size()) << las;
  }
}
