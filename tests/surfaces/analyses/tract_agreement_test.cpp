// SPDX-License-Identifier: GPL-3.0-or-later
// Tract/fabric agreement on a surface: the projected principal direction in closed form, agreement near
// 0 degrees on a constant-direction phantom (and the known angle when tracts and field differ), and the
// two populations of a crossing phantom.
#include "io/model/error.h"
#include "io/phantoms.h"
#include "support/test_env.h"
#include "surfaces/analyses/agreement.h"
#include "surfaces/slices.h"
#include "surfaces/tracking/tracking.h"

#include <cmath>

using dtf::Polylines;
using dtf::SymTensor;
using dtf::TensorField;

namespace {
const double kPi = 3.14159265358979323846;

glm::dvec3 dirOf(double azimuthDeg, double elevationDeg) {
  double az = azimuthDeg * kPi / 180, el = elevationDeg * kPi / 180;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}
SymTensor prolate(const glm::dvec3& d) {
  return SymTensor::fromMat(0.3e-3 * glm::dmat3(1.0) + 1.4e-3 * glm::outerProduct(d, d));
}
double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::min(1.0, std::abs(glm::dot(glm::normalize(a), glm::normalize(b))))) * 180 / kPi;
}

dtf::io::Phantom phantom(const char* name, double angle, double elevation, double crossing = 90,
                         int size = 40) {
  dtf::io::PhantomOptions po;
  po.size = size;
  po.angleDeg = angle;
  po.elevationDeg = elevation;
  po.crossingDeg = crossing;
  return dtf::io::makePhantom(name, po);
}

// Straight polyline through the origin along d, points every 0.5 mm for |s| <= half.
void addLine(Polylines& l, const glm::dvec3& d, double half, double z) {
  if (l.offsets.empty()) l.offsets.push_back(0);
  for (double s = -half; s <= half + 1e-9; s += 0.5)
    l.points.emplace_back(glm::dvec3(s * d.x, s * d.y, z));
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
}
} // namespace

// T' = P T P^T for a prolate tensor along d: its in-plane principal direction is the projection of d
// (T' = 0.3 P + 1.4 (Pd)(Pd)^T), with planar anisotropy 1.4|Pd|^2 / (0.6 + 1.4|Pd|^2).
TEST(Agreement, ProjectedPrincipalDirectionClosedForm) {
  const glm::dvec3 n(0, 0, 1);
  for (double el : {0.0, 30.0, 60.0}) {
    const glm::dvec3 d = dirOf(40, el);
    glm::dvec3 dir;
    double aniso = 0;
    ASSERT_TRUE(dtf::surfaces::projectedPrincipalDirection(prolate(d), n, dir, 0.02, &aniso)) << el;
    EXPECT_LT(angleDeg(dir, glm::dvec3(d.x, d.y, 0)), 1e-4) << el;
    EXPECT_NEAR(std::abs(glm::dot(dir, n)), 0, 1e-9);
    const double p2 = d.x * d.x + d.y * d.y;
    EXPECT_NEAR(aniso, 1.4 * p2 / (0.6 + 1.4 * p2), 1e-5) << el;
  }
  glm::dvec3 dir;
  // Fibres along the normal: the projected tensor is isotropic in the plane, no direction.
  EXPECT_FALSE(dtf::surfaces::projectedPrincipalDirection(prolate(n), n, dir));
  EXPECT_FALSE(dtf::surfaces::projectedPrincipalDirection(SymTensor{}, n, dir));
  // Oblique normal: direction is in the plane and the projection of d.
  const glm::dvec3 n2 = glm::normalize(glm::dvec3(1, 1, 1)), d = dirOf(0, 0);
  ASSERT_TRUE(dtf::surfaces::projectedPrincipalDirection(prolate(d), n2, dir));
  EXPECT_LT(angleDeg(dir, d - glm::dot(d, n2) * n2), 1e-4);
}

// Our tracker on a constant-direction phantom tilted 25 degrees out of an axial slice: the tracts' in-plane
// tangent and the fabric direction coincide (median < 3 degrees; in fact ~0).
TEST(Agreement, ConstantPhantomAgreesNearZero) {
  const auto p = phantom("constant", 30, 25);
  const TensorField& f = p.tensors;
  dtf::surfaces::TrackingOptions o;
  o.minLengthMm = 10;
  const auto tracts =
      dtf::surfaces::trackSelect(f, dtf::surfaces::seedsOnSlice(f, 2, 20, nullptr, 3), 200, o).lines;
  ASSERT_EQ(tracts.lineCount(), 200u);
  const dtf::Mesh slice = dtf::surfaces::makeSlice(f.grid, dtf::surfaces::SliceAxis::Axial, 20);
  const auto r = dtf::surfaces::tractSurfaceAgreement(tracts, slice, f);
  ASSERT_GT(r.anglesDeg.size(), 500u);
  EXPECT_LT(r.medianDeg, 3.0);
  EXPECT_LT(r.meanDeg, 3.0);
  EXPECT_GT(r.fracBelow15, 0.99);
  EXPECT_EQ(r.histogram.size(), 9u);
  EXPECT_EQ(r.histogram[0], r.anglesDeg.size());
  EXPECT_EQ(r.skippedTangent, 0u); // 25 degrees from the plane: the projected tangent is cos 25 of it

  // Negative control: tracts along 75 degrees compared with the 30-degree field read 45 degrees.
  const auto other = phantom("constant", 75, 0);
  const auto tracts2 =
      dtf::surfaces::trackSelect(other.tensors, dtf::surfaces::seedsOnSlice(other.tensors, 2, 20, nullptr, 3),
                                 50, o)
          .lines;
  const auto r2 = dtf::surfaces::tractSurfaceAgreement(tracts2, slice, f);
  ASSERT_GT(r2.anglesDeg.size(), 100u);
  EXPECT_NEAR(r2.medianDeg, 45.0, 0.5);
  EXPECT_EQ(r2.fracBelow15, 0.0);
}

// Crossing phantom, bundles at +-25 degrees (50 degree crossing), summed where they overlap. Ground-truth
// tracts run along each bundle's centre line. Outside the overlap the fabric follows the bundle (0 deg);
// inside it the summed tensor's principal direction is the bisector, 25 deg from each bundle. So the
// histogram is bimodal with peaks at 0-10 and 20-30 deg, and per bundle the two populations split at the
// overlap edge |s| = halfWidth / sin(50 deg).
TEST(Agreement, CrossingPhantomIsBimodal) {
  const int size = 64;
  const auto p = phantom("crossing", 0, 0, 50, size);
  const TensorField& f = p.tensors;
  const double halfWidth = 0.12 * (size - 1), overlapEdge = halfWidth / std::sin(50 * kPi / 180);
  const dtf::Mesh slice = dtf::surfaces::makeSlice(f.grid, dtf::surfaces::SliceAxis::Axial, size / 2);
  const double z = f.grid.toWorld(glm::dvec3(0, 0, size / 2)).z;
  Polylines tracts;
  const glm::dvec3 d1 = dirOf(-25, 0), d2 = dirOf(25, 0);
  addLine(tracts, d1, 28, z);
  addLine(tracts, d2, 28, z);
  dtf::surfaces::AgreementOptions ao;
  ao.bins = 9;
  const auto r = dtf::surfaces::tractSurfaceAgreement(tracts, slice, f, ao);
  ASSERT_EQ(r.anglesDeg.size(), tracts.points.size());
  const auto& h = r.histogram;
  std::string text;
  for (auto c : h)
    text += std::to_string(c) + " ";
  EXPECT_GT(h[0], h[1]) << text;
  EXPECT_GT(h[2], h[1]) << text;
  EXPECT_GT(h[2], r.anglesDeg.size() / 5) << text;
  for (std::size_t b = 3; b < h.size(); ++b)
    EXPECT_EQ(h[b], 0u) << text;

  // Per point: 0 deg well outside the overlap, 25 deg well inside, for both bundles.
  for (std::size_t i = 0; i < r.anglesDeg.size(); ++i) {
    const glm::dvec3 q(tracts.points[i]);
    const double s = glm::length(glm::dvec2(q.x, q.y));
    if (s > overlapEdge + 1.5) {
      EXPECT_LT(r.anglesDeg[i], 0.5) << "s = " << s;
    } else if (s < overlapEdge - 1.5) {
      EXPECT_NEAR(r.anglesDeg[i], 25.0, 0.5) << "s = " << s;
    }
  }
  EXPECT_EQ(r.lineOf.front(), 0u);
  EXPECT_EQ(r.lineOf.back(), 1u);

  // At 90 degrees the overlap is in-plane isotropic: those points have no fabric direction and are skipped,
  // and the rest agree.
  const auto p90 = phantom("crossing", 0, 0, 90, size);
  Polylines t90;
  addLine(t90, dirOf(-45, 0), 28, z);
  addLine(t90, dirOf(45, 0), 28, z);
  const auto r90 = dtf::surfaces::tractSurfaceAgreement(t90, slice, p90.tensors, ao);
  EXPECT_GT(r90.skippedDegenerate, 20u);
  EXPECT_LT(r90.medianDeg, 1.0);
  EXPECT_GT(r90.fracBelow15, 0.9);
}

TEST(Agreement, BadOptionsAndEmptySurface) {
  const auto p = phantom("constant", 0, 0);
  Polylines none;
  EXPECT_THROW(dtf::surfaces::tractSurfaceAgreement(none, dtf::Mesh{}, p.tensors), dtf::InputError);
  dtf::surfaces::AgreementOptions ao;
  ao.bins = 0;
  const dtf::Mesh slice = dtf::surfaces::makeSlice(p.tensors.grid, dtf::surfaces::SliceAxis::Axial, 5);
  EXPECT_THROW(dtf::surfaces::tractSurfaceAgreement(none, slice, p.tensors, ao), dtf::UsageError);
  const auto r = dtf::surfaces::tractSurfaceAgreement(none, slice, p.tensors);
  EXPECT_TRUE(r.anglesDeg.empty());
  EXPECT_EQ(r.nearPoints, 0u);
}
