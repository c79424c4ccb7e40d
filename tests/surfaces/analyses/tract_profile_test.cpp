// SPDX-License-Identifier: GPL-3.0-or-later
// Tract profiles on synthetic bundles with closed-form answers: arc-length resampling, a linear scalar field
// along straight lines on an oblique grid (trilinear sampling is exact there), orientation flips (by the
// first streamline and by a start point), the zero-padded edge sampling DIPY uses, gauss weights against an
// independent cofactor-inverse reference, the spread and the median, the seeded bootstrap and bad bundles.
#include "io/model/error.h"
#include "surfaces/analyses/tract_profile.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using dtf::Polylines;
using dtf::ScalarVolume;
namespace sf = dtf::surfaces;

namespace {

void addLine(Polylines& l, const std::vector<glm::vec3>& pts) {
  if (l.offsets.empty()) l.offsets.push_back(0);
  l.points.insert(l.points.end(), pts.begin(), pts.end());
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
}

// A straight line from a to b with `count` points spaced unevenly (quadratically), so that resampling by
// arc length, not by vertex, is what puts the nodes evenly.
std::vector<glm::vec3> unevenLine(const glm::dvec3& a, const glm::dvec3& b, int count) {
  std::vector<glm::vec3> p;
  for (int i = 0; i < count; ++i) {
    const double t = std::pow(static_cast<double>(i) / (count - 1), 2.0);
    p.emplace_back(glm::mix(a, b, t));
  }
  return p;
}

// value(x, y, z) = a + b x + c y + d z in world mm, sampled on an oblique grid: 2 mm voxels, x flipped
// (LAS), rotated 20 degrees about z, covering roughly [-60, 60]^3.
ScalarVolume linearField(double a, double b, double c, double d) {
  const double ang = 20.0 * 3.14159265358979323846 / 180.0;
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(-2 * std::cos(ang), -2 * std::sin(ang), 0, 0);
  m[1] = glm::dvec4(-2 * std::sin(ang), 2 * std::cos(ang), 0, 0);
  m[2] = glm::dvec4(0, 0, 2, 0);
  const dtf::Grid g0 = dtf::Grid::fromAffine(glm::ivec3(80, 80, 64), m);
  m[3] = glm::dvec4(-(g0.toWorld(glm::dvec3(40, 40, 32))), 1.0); // centre the grid on the origin
  m[3].w = 1;
  ScalarVolume v(dtf::Grid::fromAffine(glm::ivec3(80, 80, 64), m), 1);
  for (int k = 0; k < 64; ++k)
    for (int j = 0; j < 80; ++j)
      for (int i = 0; i < 80; ++i) {
        const glm::dvec3 w = v.grid.toWorld(glm::dvec3(i, j, k));
        v.at(i, j, k) = static_cast<float>(a + b * w.x + c * w.y + d * w.z);
      }
  return v;
}

// Lines along x from x = -20 to 20 at the given y (z = 5), each with 9 unevenly spaced points.
Polylines parallelLines(const std::vector<double>& ys, const std::vector<bool>& reversed = {}) {
  Polylines l;
  for (std::size_t i = 0; i < ys.size(); ++i) {
    glm::dvec3 a(-20, ys[i], 5), b(20, ys[i], 5);
    if (i < reversed.size() && reversed[i]) std::swap(a, b);
    addLine(l, unevenLine(a, b, 9));
  }
  return l;
}

double nodeX(int k, int n) {
  return -20.0 + 40.0 * k / (n - 1);
}

// The inverse of a symmetric 3x3 matrix by cofactors (independent of the engine's glm/eigen path).
std::array<std::array<double, 3>, 3> cofactorInverse(const std::array<std::array<double, 3>, 3>& a) {
  std::array<std::array<double, 3>, 3> c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int r0 = (i + 1) % 3, r1 = (i + 2) % 3, c0 = (j + 1) % 3, c1 = (j + 2) % 3;
      c[j][i] = a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]; // cyclic minors carry their sign
    }
  const double det = a[0][0] * c[0][0] + a[0][1] * c[1][0] + a[0][2] * c[2][0];
  for (auto& row : c)
    for (double& x : row)
      x /= det;
  return c;
}

} // namespace

TEST(TractProfile, ResamplesByArcLengthNotByVertex) {
  const auto line = unevenLine({0, 0, 0}, {10, 0, 0}, 7);
  const auto r = sf::resampleByArcLength(line.data(), line.size(), 11);
  ASSERT_EQ(r.size(), 11u);
  for (int k = 0; k < 11; ++k) {
    EXPECT_NEAR(r[k].x, k, 1e-5) << k;
    EXPECT_NEAR(r[k].y, 0, 1e-12);
  }
  // Around a corner: an L of two 4 mm legs, 5 nodes 2 mm apart along it.
  const std::vector<glm::vec3> ell = {{0, 0, 0}, {1, 0, 0}, {4, 0, 0}, {4, 4, 0}};
  const auto c = sf::resampleByArcLength(ell.data(), ell.size(), 5);
  const std::vector<glm::dvec3> want = {{0, 0, 0}, {2, 0, 0}, {4, 0, 0}, {4, 2, 0}, {4, 4, 0}};
  for (int k = 0; k < 5; ++k)
    EXPECT_LT(glm::distance(c[k], want[k]), 1e-6) << k;
  EXPECT_NEAR(sf::polylineLength(ell.data(), ell.size()), 8.0, 1e-12);
}

// Trilinear interpolation reproduces a linear field exactly, so each node's value is the field at the node.
TEST(TractProfile, LinearFieldAlongStraightLinesIsExact) {
  const ScalarVolume field = linearField(0.3, 0.01, 0.002, -0.004);
  const std::vector<double> ys = {-6, -3, -1, 0, 2, 5, 9};
  const Polylines lines = parallelLines(ys);
  double meanY = 0;
  for (double y : ys)
    meanY += y / ys.size();
  double varY = 0;
  for (double y : ys)
    varY += (y - meanY) * (y - meanY) / (ys.size() - 1);
  for (auto w : {sf::ProfileWeights::Gauss, sf::ProfileWeights::Mean, sf::ProfileWeights::Median}) {
    sf::ProfileOptions o;
    o.nodes = 21;
    o.weights = w;
    o.bootstrap = 200;
    const auto p = sf::profileBundle(lines, nullptr, {{"lin", &field}}, o);
    ASSERT_EQ(p.streamlines, ys.size());
    EXPECT_EQ(p.flipped, 0u);
    ASSERT_EQ(p.scalars.size(), 1u);
    const auto& s = p.scalars[0];
    for (int k = 0; k < o.nodes; ++k) {
      const double x = nodeX(k, o.nodes);
      EXPECT_EQ(s.streamlines[k], ys.size());
      if (w == sf::ProfileWeights::Mean) {
        EXPECT_NEAR(s.mean[k], 0.3 + 0.01 * x + 0.002 * meanY - 0.004 * 5, 1e-5) << k;
        EXPECT_NEAR(s.sd[k], 0.002 * std::sqrt(varY), 1e-5) << k;
        EXPECT_NEAR(p.core[k].y, meanY, 1e-4);
      }
      if (w == sf::ProfileWeights::Median) {
        EXPECT_NEAR(s.mean[k], 0.3 + 0.01 * x + 0.002 * 0 - 0.004 * 5, 1e-5) << k; // median y is 0
        EXPECT_NEAR(s.sd[k], 0.002 * std::sqrt(varY), 1e-5) << k;
      }
      // Every estimate lies between the smallest and largest line's value; the interval brackets it.
      EXPECT_GE(s.mean[k], 0.3 + 0.01 * x - 0.002 * 6 - 0.02 - 1e-5);
      EXPECT_LE(s.mean[k], 0.3 + 0.01 * x + 0.002 * 9 - 0.02 + 1e-5);
      EXPECT_LE(s.ciLow[k], s.mean[k] + 1e-9) << k;
      EXPECT_GE(s.ciHigh[k], s.mean[k] - 1e-9) << k;
      EXPECT_GT(s.ciHigh[k] - s.ciLow[k], 1e-4) << k;
      EXPECT_NEAR(p.core[k].x, x, 1e-4);
      EXPECT_NEAR(p.core[k].z, 5, 1e-4);
    }
  }
}

// A field that varies only along the lines: every streamline has the same value at a node, so the spread is
// zero and the interval collapses onto the value.
TEST(TractProfile, ValuesAlongTheLinesOnlyHaveNoSpread) {
  const ScalarVolume field = linearField(0.5, -0.008, 0, 0);
  const Polylines lines = parallelLines({-2, -1, 0, 1, 3});
  sf::ProfileOptions o;
  o.nodes = 9;
  const auto p = sf::profileBundle(lines, nullptr, {{"x", &field}}, o);
  for (int k = 0; k < o.nodes; ++k) {
    const double want = 0.5 - 0.008 * nodeX(k, o.nodes);
    EXPECT_NEAR(p.scalars[0].mean[k], want, 1e-5);
    EXPECT_NEAR(p.scalars[0].sd[k], 0, 1e-5);
    EXPECT_NEAR(p.scalars[0].ciLow[k], want, 1e-5);
    EXPECT_NEAR(p.scalars[0].ciHigh[k], want, 1e-5);
  }
}

TEST(TractProfile, StreamlinesStoredBackwardsAreFlippedToAgreeWithTheFirst) {
  const ScalarVolume field = linearField(0.3, 0.01, 0.002, 0);
  const std::vector<double> ys = {-4, -1, 0, 2, 3, 7};
  sf::ProfileOptions o;
  o.nodes = 15;
  o.bootstrap = 100;
  const auto straight = sf::profileBundle(parallelLines(ys), nullptr, {{"f", &field}}, o);
  const auto mixed = sf::profileBundle(parallelLines(ys, {false, true, true, false, true, false}), nullptr,
                                       {{"f", &field}}, o);
  EXPECT_EQ(mixed.flipped, 3u);
  for (int k = 0; k < o.nodes; ++k) {
    EXPECT_NEAR(mixed.scalars[0].mean[k], straight.scalars[0].mean[k], 1e-9);
    EXPECT_NEAR(mixed.scalars[0].ciLow[k], straight.scalars[0].ciLow[k], 1e-9);
  }
  // The first streamline sets the direction: with it reversed, the whole profile runs from x = 20.
  const auto reversedFirst = sf::profileBundle(parallelLines(ys, {true, false, false, false, false, false}),
                                               nullptr, {{"f", &field}}, o);
  EXPECT_EQ(reversedFirst.flipped, 5u);
  for (int k = 0; k < o.nodes; ++k)
    EXPECT_NEAR(reversedFirst.scalars[0].mean[k], straight.scalars[0].mean[o.nodes - 1 - k], 1e-9);
  // A start point near x = 20 turns every streamline to start there.
  o.start = glm::dvec3(25, 0, 5);
  const auto fromStart = sf::profileBundle(parallelLines(ys, {false, true, true, false, true, false}),
                                           nullptr, {{"f", &field}}, o);
  EXPECT_EQ(fromStart.flipped, 3u);
  for (int k = 0; k < o.nodes; ++k)
    EXPECT_NEAR(fromStart.scalars[0].mean[k], straight.scalars[0].mean[o.nodes - 1 - k], 1e-9);
  EXPECT_EQ(sf::nodeAxisLabel(fromStart.core.front(), fromStart.core.back()), "right → left");
  EXPECT_EQ(sf::nodeAxisLabel(straight.core.front(), straight.core.back()), "left → right");
  EXPECT_EQ(sf::nodeAxisLabel({0, 0, -40}, {3, -2, 30}), "inferior → superior");
  EXPECT_EQ(sf::nodeAxisLabel({0, 40, 0}, {3, -30, 2}), "anterior → posterior");
  EXPECT_EQ(sf::nodeAxisLabel({13, 19, 64}, {-5, 22, 83}), "inferior right → superior left");
  EXPECT_EQ(sf::nodeAxisLabel({1, 1, 1}, {1, 1, 1}), "start → end");
}

// The orientation test on 12-point resamplings: a U-shaped streamline and its reverse.
TEST(TractProfile, OrientationComparesSummedDistances) {
  std::vector<glm::dvec3> ref, line;
  for (int i = 0; i < 12; ++i)
    ref.push_back({double(i), 0, 0});
  for (int i = 0; i < 12; ++i)
    line.push_back({11.0 - i, 1, 0});
  EXPECT_TRUE(sf::fitsBetterReversed(line, ref));
  std::reverse(line.begin(), line.end());
  EXPECT_FALSE(sf::fitsBetterReversed(line, ref));
  // A symmetric line (the same either way) is kept as it is.
  std::vector<glm::dvec3> sym;
  for (int i = 0; i < 12; ++i)
    sym.push_back({5.5, double(i < 6 ? i : 11 - i), 0});
  EXPECT_FALSE(sf::fitsBetterReversed(sym, ref));
}

// DIPY's interpolate_scalar_3d on a 4x4x4 volume of ones (measured with DIPY 1.6): neighbours outside the
// grid count as 0, and positions at or beyond one voxel outside give 0.
TEST(TractProfile, SamplesWithZeroPaddingAsDipy) {
  ScalarVolume ones(dtf::Grid::fromAffine(glm::ivec3(4), glm::dmat4(1.0)), 1, 1.0f);
  const std::vector<std::pair<glm::dvec3, double>> cases = {
      {{-0.5, 1, 1}, 0.5},   {{3.5, 1, 1}, 0.5},       {{-1.0, 1, 1}, 0.0},     {{3, 1, 1}, 1.0},
      {{-0.99, 1, 1}, 0.01}, {{3.2, 3.2, 3.2}, 0.512}, {{1.5, 2.5, 0.25}, 1.0}, {{4.0, 1, 1}, 0.0}};
  for (const auto& [p, want] : cases)
    EXPECT_NEAR(sf::sampleZeroPadded(ones, p), want, 1e-9) << p.x;
  // The affine is applied: 2 mm voxels shifted by 10 mm.
  glm::dmat4 m(2.0);
  m[3] = glm::dvec4(10, 0, 0, 1);
  ScalarVolume ramp(dtf::Grid::fromAffine(glm::ivec3(4), m), 1);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        ramp.at(i, j, k) = float(i);
  EXPECT_NEAR(sf::sampleZeroPadded(ramp, {13, 2, 2}), 1.5, 1e-9);
  EXPECT_NEAR(sf::sampleZeroPadded(ramp, {8, 2, 2}), 0.0, 1e-9);
}

TEST(TractProfile, GaussWeightsMatchAnIndependentMahalanobisReference) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  std::vector<glm::dvec3> pos;
  for (int s = 0; s < 12; ++s)
    pos.push_back({3 * g(rng) + 10, 1.5 * g(rng) + 0.8 * g(rng), 0.5 * g(rng) - 4});
  const auto w = sf::nodeWeights(pos, sf::ProfileWeights::Gauss);
  // Reference: mean, covariance / n, cofactor inverse, 1 / sqrt(d^T C^-1 d), normalised.
  glm::dvec3 m(0.0);
  for (const auto& p : pos)
    m += p / double(pos.size());
  std::array<std::array<double, 3>, 3> c{};
  for (const auto& p : pos)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c[a][b] += (p[a] - m[a]) * (p[b] - m[b]) / double(pos.size());
  const auto ci = cofactorInverse(c);
  std::vector<double> ref;
  double sum = 0;
  for (const auto& p : pos) {
    double q = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        q += (p[a] - m[a]) * ci[a][b] * (p[b] - m[b]);
    ref.push_back(1 / std::sqrt(q));
    sum += ref.back();
  }
  ASSERT_EQ(w.size(), pos.size());
  double total = 0;
  for (std::size_t s = 0; s < pos.size(); ++s) {
    EXPECT_NEAR(w[s], ref[s] / sum, 1e-9) << s;
    total += w[s];
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
}

TEST(TractProfile, GaussWeightsInDegenerateCases) {
  using sf::ProfileWeights;
  EXPECT_EQ(sf::nodeWeights({{1, 2, 3}}, ProfileWeights::Gauss), std::vector<double>{1.0});
  // Every streamline at one place: equal weights (DIPY: all covariance entries within 1e-8 of 0).
  const auto same = sf::nodeWeights({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, ProfileWeights::Gauss);
  for (double x : same)
    EXPECT_NEAR(x, 1.0 / 3, 1e-12);
  // Two streamlines (a rank-1 covariance): each is one unit from the mean along their line.
  const auto two = sf::nodeWeights({{0, 0, 0}, {4, 2, 1}}, ProfileWeights::Gauss);
  EXPECT_NEAR(two[0], 0.5, 1e-9);
  EXPECT_NEAR(two[1], 0.5, 1e-9);
  // Coplanar positions (rank 2): the pseudo-inverse in the plane. A square's corners and its centre: the
  // centre lies on the mean and takes the whole weight.
  const auto square =
      sf::nodeWeights({{-1, -1, 7}, {1, -1, 7}, {1, 1, 7}, {-1, 1, 7}, {0, 0, 7}}, ProfileWeights::Gauss);
  for (int s = 0; s < 4; ++s)
    EXPECT_NEAR(square[s], 0, 1e-12);
  EXPECT_NEAR(square[4], 1, 1e-12);
  // Without the centre: four corners, equal distances.
  const auto corners =
      sf::nodeWeights({{-1, -1, 7}, {1, -1, 7}, {1, 1, 7}, {-1, 1, 7}}, ProfileWeights::Gauss);
  for (double x : corners)
    EXPECT_NEAR(x, 0.25, 1e-9);
  // A rectangle 6 x 2 with a fifth point at (1, 0): in the plane, x is scaled by its spread.
  const std::vector<glm::dvec3> rect = {{-3, -1, 0}, {3, -1, 0}, {3, 1, 0}, {-3, 1, 0}, {1, 0, 0}};
  const auto rw = sf::nodeWeights(rect, ProfileWeights::Gauss);
  // Reference in 2D: mean (0.2, 0), covariance diag(var x, var y), both by closed form.
  const double mx = 0.2;
  double vx = 0, vy = 0;
  for (const auto& p : rect)
    vx += (p.x - mx) * (p.x - mx) / 5, vy += p.y * p.y / 5;
  std::vector<double> ref;
  double sum = 0;
  for (const auto& p : rect) {
    ref.push_back(1 / std::sqrt((p.x - mx) * (p.x - mx) / vx + p.y * p.y / vy));
    sum += ref.back();
  }
  for (int s = 0; s < 5; ++s)
    EXPECT_NEAR(rw[s], ref[s] / sum, 1e-9) << s;
  for (double x : sf::nodeWeights(rect, ProfileWeights::Mean))
    EXPECT_NEAR(x, 0.2, 1e-15);
}

// Gauss weighting on a bundle: lines at y = y_s on a field that varies with y alone; the profile at every
// node is sum_s w_s value_s with the weights of the node's positions.
TEST(TractProfile, GaussProfileIsTheWeightedMeanOfTheNodes) {
  const ScalarVolume field = linearField(0.4, 0, 0.01, 0);
  const std::vector<double> ys = {-9, -4, -1, 0, 1, 2, 6};
  Polylines lines;
  // Lines fan out in z towards one end, so the node covariance is full rank and changes along the bundle.
  for (std::size_t s = 0; s < ys.size(); ++s)
    addLine(lines, unevenLine({-20, ys[s], 0}, {20, ys[s] + 0.3 * s, 0.5 * ys[s] * ys[s] / 10 + s}, 11));
  sf::ProfileOptions o;
  o.nodes = 7;
  o.bootstrap = 0;
  const auto p = sf::profileBundle(lines, nullptr, {{"y", &field}}, o);
  for (int k = 0; k < o.nodes; ++k) {
    std::vector<glm::dvec3> pos;
    for (std::size_t s = 0; s < ys.size(); ++s) {
      const auto r = sf::resampleByArcLength(lines.points.data() + lines.offsets[s], 11, o.nodes);
      pos.push_back(r[k]);
    }
    const auto w = sf::nodeWeights(pos, sf::ProfileWeights::Gauss);
    double mean = 0, w2 = 0, ss = 0;
    glm::dvec3 core(0.0);
    for (std::size_t s = 0; s < ys.size(); ++s) {
      mean += w[s] * (0.4 + 0.01 * pos[s].y);
      w2 += w[s] * w[s];
      core += w[s] * pos[s];
    }
    for (std::size_t s = 0; s < ys.size(); ++s)
      ss += w[s] * std::pow(0.4 + 0.01 * pos[s].y - mean, 2);
    EXPECT_NEAR(p.scalars[0].mean[k], mean, 1e-5) << k;
    EXPECT_NEAR(p.scalars[0].sd[k], std::sqrt(ss / (1 - w2)), 1e-5) << k;
    EXPECT_LT(glm::distance(p.core[k], core), 1e-6) << k;
    EXPECT_TRUE(std::isnan(p.scalars[0].ciLow[k])); // no bootstrap asked for
  }
}

TEST(TractProfile, MedianOfOddAndEvenCounts) {
  const ScalarVolume field = linearField(0, 0, 1, 0); // the value is y
  sf::ProfileOptions o;
  o.nodes = 3;
  o.weights = sf::ProfileWeights::Median;
  o.bootstrap = 0;
  auto odd = sf::profileBundle(parallelLines({1, 2, 10}), nullptr, {{"y", &field}}, o);
  EXPECT_NEAR(odd.scalars[0].mean[1], 2, 1e-5);
  auto even = sf::profileBundle(parallelLines({1, 2, 4, 10}), nullptr, {{"y", &field}}, o);
  EXPECT_NEAR(even.scalars[0].mean[1], 3, 1e-5);
}

TEST(TractProfile, BootstrapIsSeededAndIndependentOfThreads) {
  const ScalarVolume field = linearField(0.3, 0.01, 0.02, 0);
  const Polylines lines = parallelLines({-6, -3, -1, 0, 2, 5, 9, 11});
  sf::ProfileOptions o;
  o.nodes = 5;
  o.bootstrap = 300;
  o.threads = 1;
  o.weights = sf::ProfileWeights::Mean;
  const auto a = sf::profileBundle(lines, nullptr, {{"f", &field}}, o);
  o.threads = 3;
  const auto b = sf::profileBundle(lines, nullptr, {{"f", &field}}, o);
  o.seed = 2;
  const auto c = sf::profileBundle(lines, nullptr, {{"f", &field}}, o);
  bool differs = false;
  for (int k = 0; k < o.nodes; ++k) {
    EXPECT_EQ(a.scalars[0].ciLow[k], b.scalars[0].ciLow[k]);
    EXPECT_EQ(a.scalars[0].ciHigh[k], b.scalars[0].ciHigh[k]);
    differs = differs || a.scalars[0].ciLow[k] != c.scalars[0].ciLow[k];
    // The bootstrap interval of a mean of 8 values with sample sd s: about mean +- 1.96 s sqrt(7 / 8) /
    // sqrt(8) (the resamples' spread is the population's), here within a quarter of that.
    const double half = 1.96 * a.scalars[0].sd[k] * std::sqrt(7.0 / 8.0) / std::sqrt(8.0);
    EXPECT_NEAR(a.scalars[0].ciHigh[k] - a.scalars[0].ciLow[k], 2 * half, 0.25 * 2 * half) << k;
  }
  EXPECT_TRUE(differs);
}

TEST(TractProfile, SkipsPointsAndRefusesEmptyBundles) {
  const ScalarVolume field = linearField(0.3, 0, 0, 0);
  Polylines lines = parallelLines({0, 1});
  addLine(lines, {{1, 2, 3}});            // one point
  addLine(lines, {{1, 2, 3}, {1, 2, 3}}); // no length
  sf::ProfileOptions o;
  o.bootstrap = 10;
  const auto p = sf::profileBundle(lines, nullptr, {{"f", &field}}, o);
  EXPECT_EQ(p.streamlines, 2u);
  EXPECT_EQ(p.skipped, 2u);
  const std::vector<std::uint32_t> bad = {2, 3};
  EXPECT_THROW(sf::profileBundle(lines, &bad, {{"f", &field}}, o), dtf::InputError);
  const std::vector<std::uint32_t> none;
  EXPECT_THROW(sf::profileBundle(lines, &none, {{"f", &field}}, o), dtf::InputError);
  const std::vector<std::uint32_t> outside = {0, 9};
  EXPECT_THROW(sf::profileBundle(lines, &outside, {{"f", &field}}, o), dtf::InputError);
  EXPECT_THROW(sf::profileBundle(lines, nullptr, {{"f", nullptr}}, o), dtf::InputError);
  o.nodes = 1;
  EXPECT_THROW(sf::profileBundle(lines, nullptr, {{"f", &field}}, o), dtf::UsageError);
}
