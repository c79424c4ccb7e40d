// SPDX-License-Identifier: GPL-3.0-or-later
// The cone of uncertainty: directionSpread on samples with a known spread, the wild bootstrap's fit equal to
// fitTensors, and its calibration on a simulated phantom (known directions, Rician noise at three SNRs, a
// 6 x b=0 + 60-direction b=1000 scheme): the true direction lies inside the 95 % cone in about 95 % of
// voxels and the cone widens as the SNR falls.
#include "io/diffusion/dwi.h"
#include "io/diffusion/uncertainty.h"
#include "io/model/error.h"
#include "io/model/tensor.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <random>

using namespace dtf;
using namespace dtf::io;

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
}

// 6 b=0 volumes and 60 directions at b = 1000 s/mm^2 (random unit vectors, fixed seed), in the bvec frame.
void scheme(std::vector<double>& bvals, std::vector<glm::dvec3>& bvecs) {
  std::mt19937 rng(11);
  for (int i = 0; i < 6; ++i) {
    bvals.push_back(0);
    bvecs.emplace_back(0.0);
  }
  for (int i = 0; i < 60; ++i) {
    bvals.push_back(1000);
    bvecs.push_back(randomUnit(rng));
  }
}

struct Phantom {
  Dwi dwi;
  std::vector<glm::dvec3> truth; // per voxel, world
};

// dims.x * dims.y * dims.z voxels, each a prolate tensor (1.7, 0.3, 0.3) 1e-3 mm^2/s (FA 0.80) along a
// random world direction, S0 = 1000, Rician noise of sigma = S0 / snr. Identity affine: FSL's bvec frame is
// world with x negated (det > 0), so the signal is made with the gradients negated in x.
Phantom phantom(double snr, unsigned seed, glm::ivec3 dims = {12, 12, 6}) {
  std::vector<double> bvals;
  std::vector<glm::dvec3> bvecs;
  scheme(bvals, bvecs);
  const Grid grid = Grid::fromAffine(dims, glm::dmat4(1.0));
  const int n = static_cast<int>(bvals.size());
  Volume<float> sig(grid, n);
  Phantom p;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1000.0 / snr);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
    const glm::dvec3 e1 = randomUnit(rng);
    p.truth.push_back(e1);
    const glm::dmat3 d = 0.3e-3 * glm::dmat3(1.0) + 1.4e-3 * glm::outerProduct(e1, e1);
    for (int i = 0; i < n; ++i) {
      glm::dvec3 g = glm::length(bvecs[i]) > 0 ? glm::normalize(bvecs[i]) : glm::dvec3(0.0);
      g.x = -g.x;
      const double s = 1000.0 * std::exp(-bvals[i] * glm::dot(g, d * g));
      const double re = s + noise(rng), im = noise(rng);
      sig.data[v * n + i] = static_cast<float>(std::sqrt(re * re + im * im));
    }
  }
  p.dwi = makeDwi(std::move(sig), bvals, bvecs);
  return p;
}

MaskVolume fullMask(const Grid& g) {
  return MaskVolume(g, 1, 1);
}

double angleDeg(glm::dvec3 a, glm::dvec3 b) {
  return std::acos(std::min(1.0, std::abs(glm::dot(glm::normalize(a), glm::normalize(b))))) * 180.0 / kPi;
}

} // namespace

TEST(DirectionSpread, RingOfSamplesAtKnownAngle) {
  // 100 samples at exactly 20 degrees from z on a ring, half with flipped sign: the dyadic mean is z and
  // every angle is 20, so the cone is 20 whatever the percentile.
  std::vector<glm::vec3> d;
  for (int i = 0; i < 100; ++i) {
    const double phi = 2 * kPi * i / 100.0, t = 20.0 * kPi / 180.0;
    glm::vec3 v(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
    d.push_back(i % 2 ? -v : v);
  }
  d.emplace_back(0.0f); // skipped
  const DirectionSpread s = directionSpread(d.data(), d.size());
  EXPECT_EQ(s.samples, 100);
  EXPECT_NEAR(std::abs(s.mean.z), 1.0, 1e-9);
  EXPECT_NEAR(s.coneDeg, 20.0, 1e-3);
}

TEST(DirectionSpread, PercentileRank) {
  // Angles 1..100 degrees from x in the xy plane (sign alternating): ceil(0.95*100) = 95th smallest.
  std::vector<glm::vec3> d;
  d.emplace_back(1.0f, 0.0f, 0.0f);
  for (int i = 1; i < 100; ++i) {
    const double t = (i * 0.85) * kPi / 180.0; // up to 84 degrees, all on one side: the mean tilts
    d.emplace_back(std::cos(t), std::sin(t), 0.0);
  }
  const DirectionSpread s = directionSpread(d.data(), d.size(), 95.0);
  std::vector<double> a;
  for (const auto& v : d)
    a.push_back(angleDeg(glm::dvec3(v), s.mean));
  std::sort(a.begin(), a.end());
  EXPECT_NEAR(s.coneDeg, a[94], 1e-4);
}

TEST(Bootstrap, FitEqualsFitTensors) {
  Phantom p = phantom(20, 3, {5, 4, 3});
  const MaskVolume mask = fullMask(p.dwi.signal.grid);
  for (FitMethod m : {FitMethod::Wls, FitMethod::Ols}) {
    FitOptions o;
    o.method = m;
    o.threads = 2;
    UncertaintyMaps maps;
    BootstrapOptions b;
    b.resamples = 20;
    const TensorField boot = bootstrapTensors(p.dwi, &mask, o, b, maps);
    const TensorField fit = fitTensors(p.dwi, &mask, o);
    for (std::size_t v = 0; v < fit.tensors.size(); ++v) {
      ASSERT_EQ(boot.valid[v], fit.valid[v]);
      const auto a = boot.tensors[v].components(), c = fit.tensors[v].components();
      for (int i = 0; i < 6; ++i)
        EXPECT_NEAR(a[i], c[i], 1e-8) << "voxel " << v;
      EXPECT_TRUE(maps.cone.data[v] >= 0 && maps.cone.data[v] <= 90);
      EXPECT_TRUE(maps.faSd.data[v] >= 0 && maps.faSd.data[v] < 0.5);
    }
  }
}

TEST(Bootstrap, DeterministicAndThreadIndependent) {
  Phantom p = phantom(15, 4, {6, 5, 4});
  const MaskVolume mask = fullMask(p.dwi.signal.grid);
  FitOptions o1, o3;
  o1.threads = 1;
  o3.threads = 3;
  UncertaintyMaps m1, m3;
  BootstrapOptions b;
  b.resamples = 50;
  bootstrapTensors(p.dwi, &mask, o1, b, m1);
  bootstrapTensors(p.dwi, &mask, o3, b, m3);
  EXPECT_EQ(m1.cone.data, m3.cone.data);
  EXPECT_EQ(m1.faSd.data, m3.faSd.data);
}

TEST(Bootstrap, MaskAndInputChecks) {
  Phantom p = phantom(20, 5, {4, 4, 2});
  MaskVolume mask = fullMask(p.dwi.signal.grid);
  mask.data[3] = 0;
  UncertaintyMaps maps;
  BootstrapOptions b;
  b.resamples = 10;
  bootstrapTensors(p.dwi, &mask, FitOptions{}, b, maps);
  EXPECT_TRUE(std::isnan(maps.cone.data[3]));
  EXPECT_TRUE(std::isnan(maps.faSd.data[3]));
  EXPECT_FALSE(std::isnan(maps.cone.data[4]));
  b.resamples = 1;
  EXPECT_THROW(bootstrapTensors(p.dwi, &mask, FitOptions{}, b, maps), InputError);
  b.resamples = 10;
  b.percentile = 100;
  EXPECT_THROW(bootstrapTensors(p.dwi, &mask, FitOptions{}, b, maps), InputError);
}

TEST(Bootstrap, ProgressAndCancel) {
  Phantom p = phantom(20, 6, {4, 4, 6});
  const MaskVolume mask = fullMask(p.dwi.signal.grid);
  UncertaintyMaps maps;
  BootstrapOptions b;
  b.resamples = 10;
  // One thread: the calling thread reports after each of the 6 slices (with more, the workers may take every
  // slice before it reports once).
  FitOptions one;
  one.threads = 1;
  double last = 0;
  int calls = 0;
  bootstrapTensors(p.dwi, &mask, one, b, maps, [&](double f) {
    EXPECT_GE(f, last);
    last = f;
    ++calls;
  });
  EXPECT_EQ(last, 1.0);
  EXPECT_GE(calls, 6);
  EXPECT_THROW(bootstrapTensors(p.dwi, &mask, FitOptions{}, b, maps,
                                [](double f) {
                                  if (f > 0.2) throw std::runtime_error("cancel");
                                }),
               std::runtime_error);
}

// Coverage: fraction of voxels whose true direction lies within the cone of the dyadic mean.
TEST(Bootstrap, CalibratedOnRicianPhantom) {
  double previousMedian = 0;
  for (double snr : {60.0, 25.0, 12.0}) {
    Phantom p = phantom(snr, static_cast<unsigned>(snr));
    const MaskVolume mask = fullMask(p.dwi.signal.grid);
    UncertaintyMaps maps;
    BootstrapOptions b;
    b.resamples = 200;
    FitOptions o;
    o.threads = 2;
    const TensorField field = bootstrapTensors(p.dwi, &mask, o, b, maps);
    int inside = 0, total = 0;
    std::vector<float> cones;
    for (std::size_t v = 0; v < field.tensors.size(); ++v) {
      ASSERT_TRUE(field.valid[v]);
      const glm::dvec3 e1 = eigenDecompose(field.tensors[v]).vectors[0];
      // The cone is measured around the resamples' dyadic mean; the truth is compared with the fitted e1,
      // which lies within a small fraction of the cone of that mean (Jones 2003 allows either centre).
      const double err = angleDeg(e1, p.truth[v]);
      ++total;
      if (err <= maps.cone.data[v]) ++inside;
      cones.push_back(maps.cone.data[v]);
    }
    std::sort(cones.begin(), cones.end());
    const double median = cones[cones.size() / 2];
    const double coverage = static_cast<double>(inside) / total;
    std::printf("SNR %.0f: median cone %.2f deg, coverage %.3f (%d voxels)\n", snr, median, coverage, total);
    EXPECT_GE(coverage, 0.90) << "SNR " << snr;
    EXPECT_LE(coverage, 0.99) << "SNR " << snr;
    EXPECT_GT(median, previousMedian * 1.5) << "the cone must widen as the SNR falls";
    previousMedian = median;
  }
}
