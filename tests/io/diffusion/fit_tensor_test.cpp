// SPDX-License-Identifier: GPL-3.0-or-later
// fitTensors on synthetic signals from known tensors: exact recovery (OLS and WLS, several gradient
// schemes, LAS/RAS/oblique affines, so the bvec-frame rotation is exercised), the WLS weighting against a
// dense reference, clamping, threading, progress/cancellation, input checks and automaticMask (phantoms with
// and without background, the warning that names --mask).
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <random>
#include <stdexcept>
#include <thread>

using namespace dtf;
using namespace dtf::io;

namespace {

struct Scheme {
  std::string name;
  std::vector<double> bvals;
  std::vector<glm::dvec3> bvecs; // bvec frame; NaN rows for b=0 where the scheme has no direction
};

std::vector<glm::dvec3> randomDirections(int n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  std::vector<glm::dvec3> out;
  for (int i = 0; i < n; ++i)
    out.push_back(glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))));
  return out;
}

std::vector<Scheme> schemes() {
  std::vector<Scheme> s;
  const double nan = std::nan("");
  { // Jones 6 directions, one b=0 with a NaN row (as small_64D.bvec).
    Scheme j{"jones6", {0}, {glm::dvec3(nan)}};
    const double d[6][3] = {{1, 0, 1}, {-1, 0, 1}, {0, 1, 1}, {0, 1, -1}, {1, 1, 0}, {-1, 1, 0}};
    for (const auto& v : d) {
      j.bvals.push_back(1000);
      j.bvecs.push_back(glm::normalize(glm::dvec3(v[0], v[1], v[2])));
    }
    s.push_back(j);
  }
  std::mt19937 rng(7);
  { // Two shells, three b=0 volumes with zero vectors.
    Scheme m{"twoShell", {0, 0, 0}, {glm::dvec3(0), glm::dvec3(0), glm::dvec3(0)}};
    for (const auto& g : randomDirections(30, rng)) {
      m.bvals.push_back(1000);
      m.bvecs.push_back(g);
    }
    for (const auto& g : randomDirections(30, rng)) {
      m.bvals.push_back(2500);
      m.bvecs.push_back(g);
    }
    s.push_back(m);
  }
  { // DSI-like: no exact b=0, lowest b = 15 with a direction (as small_101D).
    Scheme d{"noExactB0", {}, {}};
    auto dirs = randomDirections(40, rng);
    for (int i = 0; i < 40; ++i) {
      d.bvals.push_back(i == 0 ? 15.0 : 300.0 + 70.0 * i);
      d.bvecs.push_back(dirs[i]);
    }
    s.push_back(d);
  }
  return s;
}

glm::dmat3 randomRotation(std::mt19937& rng) {
  auto d = randomDirections(2, rng);
  glm::dvec3 a = d[0], b = glm::normalize(d[1] - glm::dot(d[0], d[1]) * d[0]);
  return glm::dmat3(a, b, glm::cross(a, b));
}

struct Frame {
  std::string name;
  glm::dmat4 affine;
  glm::dmat3 bvecToWorld; // written out by hand from FSL's rule, independent of bvecFrameToWorld
};

std::vector<Frame> frames() {
  std::vector<Frame> f;
  glm::dmat4 las(1.0);
  las[0][0] = -2.0; // i runs towards Left
  las[1][1] = 2.0;
  las[2][2] = 2.5;
  las[3] = glm::dvec4(50, -60, -20, 1);
  // det < 0: the bvec frame is the voxel frame; voxel i is world -x.
  f.push_back({"LAS", las, glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1)});
  glm::dmat4 ras(1.0);
  ras[0][0] = 2.0;
  ras[1][1] = 2.0;
  ras[2][2] = 2.5;
  // det > 0: FSL negates x relative to the voxel frame, and voxel i is world +x.
  f.push_back({"RAS", ras, glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1)});
  std::mt19937 rng(11);
  glm::dmat3 q = randomRotation(rng); // det +1
  glm::dmat4 obl(1.0);
  for (int c = 0; c < 3; ++c)
    obl[c] = glm::dvec4(q[c] * 1.8, 0);
  f.push_back({"obliqueDetPositive", obl, q * glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1)});
  glm::dmat3 qn = q;
  qn[0] = -qn[0]; // det -1
  glm::dmat4 obn(1.0);
  for (int c = 0; c < 3; ++c)
    obn[c] = glm::dvec4(qn[c] * 1.8, 0);
  f.push_back({"obliqueDetNegative", obn, qn});
  return f;
}

glm::dmat3 randomTensor(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.1e-3, 2.0e-3);
  glm::dmat3 r = randomRotation(rng);
  glm::dmat3 l(0.0);
  l[0][0] = u(rng);
  l[1][1] = u(rng);
  l[2][2] = u(rng);
  return r * l * glm::transpose(r);
}

// Signal of world tensors `dw` through the bvec-frame scheme: S = S0 exp(-b (M g)^T D (M g)).
Volume<float> synthesize(const Grid& grid, const Scheme& s, const glm::dmat3& bvecToWorld,
                         const std::vector<glm::dmat3>& dw, double s0) {
  const int n = static_cast<int>(s.bvals.size());
  Volume<float> v(grid, n);
  for (std::size_t idx = 0; idx < grid.voxelCount(); ++idx) {
    for (int k = 0; k < n; ++k) {
      glm::dvec3 g = s.bvecs[k];
      double q = 0;
      if (std::isfinite(g.x) && glm::length(g) > 0) {
        glm::dvec3 gw = bvecToWorld * glm::normalize(g);
        q = glm::dot(gw, dw[idx] * gw);
      }
      v.data[idx * n + k] = static_cast<float>(s0 * std::exp(-s.bvals[k] * q));
    }
  }
  return v;
}

void expectTensorNear(const SymTensor& got, const glm::dmat3& want, double tol, const std::string& what) {
  const SymTensor w = SymTensor::fromMat(want);
  auto g = got.components(), e = w.components();
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR(g[c], e[c], tol) << what << " component " << c;
}

MaskVolume fullMask(const Grid& g) {
  return MaskVolume(g, 1, 1);
}

} // namespace

TEST(FitTensors, RecoversKnownTensorsExactlyForEverySchemeFrameAndMethod) {
  std::mt19937 rng(3);
  for (const auto& frame : frames()) {
    Grid grid = Grid::fromAffine({4, 3, 3}, frame.affine);
    std::vector<glm::dmat3> dw;
    for (std::size_t i = 0; i < grid.voxelCount(); ++i)
      dw.push_back(randomTensor(rng));
    for (const auto& scheme : schemes()) {
      Dwi dwi = makeDwi(synthesize(grid, scheme, frame.bvecToWorld, dw, 1200.0), scheme.bvals, scheme.bvecs);
      MaskVolume mask = fullMask(grid);
      for (FitMethod m : {FitMethod::Ols, FitMethod::Wls}) {
        FitOptions o;
        o.method = m;
        FitStats stats;
        TensorField f = fitTensors(dwi, &mask, o, {}, &stats);
        EXPECT_EQ(stats.voxelsFitted, grid.voxelCount());
        EXPECT_EQ(stats.clampedSignals, 0u);
        EXPECT_EQ(stats.nonPositiveTensors, 0u);
        const std::string what = frame.name + "/" + scheme.name + (m == FitMethod::Ols ? "/OLS" : "/WLS");
        for (std::size_t i = 0; i < grid.voxelCount(); ++i) {
          ASSERT_TRUE(f.valid[i]) << what;
          // float32 signals limit the recovery to about 1e-10 mm^2/s; tensors are ~1e-3.
          expectTensorNear(f.tensors[i], dw[i], 2e-8, what);
        }
      }
    }
  }
}

TEST(FitTensors, BvecFrameFlipsOffDiagonalSignsForAxisAlignedLasAndRas) {
  // A tensor written in the bvec frame with positive xy and xz: for both LAS (det < 0, voxel x = world -x)
  // and RAS (det > 0, FSL negates x) the world tensor has xy and xz negated, the rest unchanged.
  const glm::dmat3 dBvec(1.5e-3, 2e-4, 1e-4, 2e-4, 4e-4, 5e-5, 1e-4, 5e-5, 3e-4);
  auto scheme = schemes()[1];
  for (const auto& frame : frames()) {
    if (frame.name != "LAS" && frame.name != "RAS") continue;
    Grid grid = Grid::fromAffine({1, 1, 1}, frame.affine);
    // Signal computed directly in the bvec frame: S = S0 exp(-b g^T D_bvec g), no rotation involved.
    std::vector<glm::dmat3> asIfWorld{dBvec};
    Dwi dwi =
        makeDwi(synthesize(grid, scheme, glm::dmat3(1.0), asIfWorld, 1000.0), scheme.bvals, scheme.bvecs);
    MaskVolume mask = fullMask(grid);
    TensorField f = fitTensors(dwi, &mask, FitOptions{});
    const SymTensor t = f.tensors[0];
    EXPECT_NEAR(t.xx, 1.5e-3, 1e-8) << frame.name;
    EXPECT_NEAR(t.xy, -2e-4, 1e-8) << frame.name;
    EXPECT_NEAR(t.xz, -1e-4, 1e-8) << frame.name;
    EXPECT_NEAR(t.yy, 4e-4, 1e-8) << frame.name;
    EXPECT_NEAR(t.yz, 5e-5, 1e-8) << frame.name;
    EXPECT_NEAR(t.zz, 3e-4, 1e-8) << frame.name;
  }
}

TEST(FitTensors, WlsMatchesDenseTwoStepReferenceOnNoisySignal) {
  // DIPY's WLS: OLS first, then weights w_v = exp(2 x_v . beta_ols) = S_hat^2. Reference solved here with
  // dense long-double normal equations, independent of the fitter's packed Cholesky.
  auto scheme = schemes()[1];
  Grid grid = Grid::fromAffine({1, 1, 1}, glm::dmat4(1.0));
  std::mt19937 rng(5);
  std::vector<glm::dmat3> dw{randomTensor(rng)};
  Volume<float> sig = synthesize(grid, scheme, glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1), dw, 800.0);
  std::normal_distribution<double> noise(0, 25);
  for (auto& s : sig.data)
    s = static_cast<float>(std::max(1.0, s + noise(rng)));
  Dwi dwi = makeDwi(sig, scheme.bvals, scheme.bvecs);
  MaskVolume mask = fullMask(grid);
  FitOptions o;
  o.method = FitMethod::Ols;
  const SymTensor ols = fitTensors(dwi, &mask, o).tensors[0];
  o.method = FitMethod::Wls;
  const SymTensor wls = fitTensors(dwi, &mask, o).tensors[0];

  const int n = static_cast<int>(scheme.bvals.size());
  auto row = [&](int v, long double* r) {
    glm::dvec3 g = dwi.gradientsWorld[v];
    long double b = dwi.bvals[v];
    long double x[7] = {1,
                        -b * g.x * g.x,
                        -2 * b * g.x * g.y,
                        -2 * b * g.x * g.z,
                        -b * g.y * g.y,
                        -2 * b * g.y * g.z,
                        -b * g.z * g.z};
    for (int i = 0; i < 7; ++i)
      r[i] = x[i];
  };
  auto solve = [&](const std::vector<long double>& w) {
    long double a[7][8] = {};
    for (int v = 0; v < n; ++v) {
      long double r[7];
      row(v, r);
      long double y = std::log(static_cast<long double>(sig.data[v]));
      for (int i = 0; i < 7; ++i) {
        for (int j = 0; j < 7; ++j)
          a[i][j] += w[v] * r[i] * r[j];
        a[i][7] += w[v] * r[i] * y;
      }
    }
    for (int c = 0; c < 7; ++c) { // Gauss-Jordan with partial pivoting
      int p = c;
      for (int r = c + 1; r < 7; ++r)
        if (std::fabs(a[r][c]) > std::fabs(a[p][c])) p = r;
      for (int j = 0; j < 8; ++j)
        std::swap(a[c][j], a[p][j]);
      for (int r = 0; r < 7; ++r) {
        if (r == c) continue;
        long double f = a[r][c] / a[c][c];
        for (int j = c; j < 8; ++j)
          a[r][j] -= f * a[c][j];
      }
    }
    std::vector<long double> beta(7);
    for (int i = 0; i < 7; ++i)
      beta[i] = a[i][7] / a[i][i];
    return beta;
  };
  auto betaOls = solve(std::vector<long double>(n, 1.0L));
  std::vector<long double> w(n);
  for (int v = 0; v < n; ++v) {
    long double r[7], pred = 0;
    row(v, r);
    for (int i = 0; i < 7; ++i)
      pred += r[i] * betaOls[i];
    w[v] = std::exp(2 * pred);
  }
  auto betaWls = solve(w);
  const float o6[6] = {ols.xx, ols.xy, ols.xz, ols.yy, ols.yz, ols.zz};
  const float w6[6] = {wls.xx, wls.xy, wls.xz, wls.yy, wls.yz, wls.zz};
  double wlsOlsGap = 0;
  for (int c = 0; c < 6; ++c) {
    EXPECT_NEAR(o6[c], static_cast<double>(betaOls[c + 1]), 1e-9) << "OLS component " << c;
    EXPECT_NEAR(w6[c], static_cast<double>(betaWls[c + 1]), 1e-9) << "WLS component " << c;
    wlsOlsGap = std::max(wlsOlsGap, std::fabs(static_cast<double>(betaWls[c + 1] - betaOls[c + 1])));
  }
  EXPECT_GT(wlsOlsGap, 1e-7) << "noise should make WLS and OLS differ, else the test proves nothing";
}

TEST(FitTensors, NonPositiveSignalIsClampedAndZeroSignalIsInvalid) {
  auto scheme = schemes()[1];
  Grid grid = Grid::fromAffine({3, 1, 1}, glm::dmat4(1.0));
  std::mt19937 rng(9);
  std::vector<glm::dmat3> dw{randomTensor(rng), randomTensor(rng), randomTensor(rng)};
  Volume<float> sig = synthesize(grid, scheme, glm::dmat3(1.0), dw, 1000.0);
  const int n = sig.components;
  sig.data[0 * n + 5] = 0.0f;          // voxel 0: one dropped-out sample
  sig.data[0 * n + 6] = -3.0f;         // and one negative
  sig.data[1 * n + 7] = std::nanf(""); // voxel 1: a NaN sample
  for (int v = 0; v < n; ++v)
    sig.data[2 * n + v] = 0.0f; // voxel 2: no signal at all
  Dwi dwi = makeDwi(sig, scheme.bvals, scheme.bvecs);
  MaskVolume mask = fullMask(grid);
  FitStats stats;
  TensorField f = fitTensors(dwi, &mask, FitOptions{}, {}, &stats);
  EXPECT_EQ(stats.clampedSignals, 3u + static_cast<std::size_t>(n));
  EXPECT_TRUE(f.valid[0]);
  EXPECT_TRUE(f.tensors[0].isFinite());
  EXPECT_TRUE(f.valid[1]);
  EXPECT_TRUE(f.tensors[1].isFinite());
  EXPECT_FALSE(f.valid[2]); // constant ln S gives the zero tensor: stored invalid
  EXPECT_EQ(stats.invalidVoxels, 1u);
}

TEST(FitTensors, OutsideMaskIsInvalidAndThreadCountDoesNotChangeResults) {
  auto scheme = schemes()[0];
  Grid grid = Grid::fromAffine({6, 5, 9}, frames()[0].affine);
  std::mt19937 rng(13);
  std::vector<glm::dmat3> dw;
  for (std::size_t i = 0; i < grid.voxelCount(); ++i)
    dw.push_back(randomTensor(rng));
  Volume<float> sig = synthesize(grid, scheme, frames()[0].bvecToWorld, dw, 500.0);
  std::normal_distribution<double> noise(0, 10);
  for (auto& s : sig.data)
    s = static_cast<float>(s + noise(rng));
  Dwi dwi = makeDwi(sig, scheme.bvals, scheme.bvecs);
  MaskVolume mask(grid, 1, 0);
  for (std::size_t i = 0; i < grid.voxelCount(); i += 2)
    mask.data[i] = 1;
  FitOptions one;
  one.threads = 1;
  FitOptions four;
  four.threads = 4;
  TensorField a = fitTensors(dwi, &mask, one), b = fitTensors(dwi, &mask, four);
  for (std::size_t i = 0; i < grid.voxelCount(); ++i) {
    EXPECT_EQ(a.valid[i], i % 2 == 0 ? 1 : 0);
    EXPECT_EQ(a.valid[i], b.valid[i]);
    EXPECT_EQ(a.tensors[i].components(), b.tensors[i].components()) << "voxel " << i;
  }
}

TEST(FitTensors, ProgressIsMonotonicFromCallingThreadAndCanCancel) {
  auto scheme = schemes()[0];
  Grid grid = Grid::fromAffine({4, 4, 12}, glm::dmat4(1.0));
  std::vector<glm::dmat3> dw(grid.voxelCount(), glm::dmat3(1e-3));
  Dwi dwi = makeDwi(synthesize(grid, scheme, glm::dmat3(1.0), dw, 100.0), scheme.bvals, scheme.bvecs);
  MaskVolume mask = fullMask(grid);
  FitOptions o;
  o.threads = 3;
  std::vector<double> seen;
  const auto caller = std::this_thread::get_id();
  bool otherThread = false;
  fitTensors(dwi, &mask, o, [&](double f) {
    seen.push_back(f);
    otherThread |= std::this_thread::get_id() != caller;
  });
  ASSERT_FALSE(seen.empty());
  EXPECT_FALSE(otherThread);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i)
    EXPECT_GE(seen[i], seen[i - 1]);
  struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("cancelled") {}
  };
  EXPECT_THROW(fitTensors(dwi, &mask, o, [](double) { throw Cancelled(); }), Cancelled);
}

TEST(FitTensors, RejectsTooFewVolumesForeignMaskAndDegenerateScheme) {
  Grid grid = Grid::fromAffine({2, 2, 2}, glm::dmat4(1.0));
  std::vector<double> b6{0, 1000, 1000, 1000, 1000, 1000};
  std::vector<glm::dvec3> g6{glm::dvec3(0), {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}};
  Dwi few = makeDwi(Volume<float>(grid, 6, 100.0f), b6, g6);
  EXPECT_THROW(fitTensors(few, nullptr, FitOptions{}), InputError);

  auto scheme = schemes()[0];
  Dwi ok = makeDwi(Volume<float>(grid, 7, 100.0f), scheme.bvals, scheme.bvecs);
  MaskVolume other(Grid::fromAffine({3, 2, 2}, glm::dmat4(1.0)), 1, 1);
  EXPECT_THROW(fitTensors(ok, &other, FitOptions{}), InputError);

  std::vector<double> b7(7, 1000.0);
  b7[0] = 0;
  std::vector<glm::dvec3> alongX(7, glm::dvec3(1, 0, 0));
  alongX[0] = glm::dvec3(0);
  Dwi degenerate = makeDwi(Volume<float>(grid, 7, 100.0f), b7, alongX);
  MaskVolume mask = fullMask(grid);
  try {
    fitTensors(degenerate, &mask, FitOptions{});
    FAIL() << "a scheme with one direction must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gradient table"), std::string::npos) << e.what();
  }
}

TEST(AutomaticMask, KeepsLargestComponentAndFillsHoles) {
  // A bright ball with a dark core (a hole), plus a small bright blob apart from it, on dark noise.
  Grid grid = Grid::fromAffine({24, 24, 20}, glm::dmat4(1.0));
  const std::vector<double> bvals{0, 1000, 1000, 1000, 1000, 1000, 1000};
  std::vector<glm::dvec3> bvecs{glm::dvec3(0), {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                                {1, 1, 0},     {0, 1, 1}, {1, 0, 1}};
  Volume<float> sig(grid, 7, 0.0f);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> bg(0.0f, 20.0f);
  std::size_t ballVoxels = 0;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double r = glm::length(glm::dvec3(i - 10, j - 10, k - 10));
        float v = bg(rng);
        if (r <= 7) {
          v = r <= 2 ? 10.0f : 900.0f; // dark core inside the ball
          ++ballVoxels;
        }
        if (glm::length(glm::dvec3(i - 21, j - 21, k - 3)) <= 1.5) v = 900.0f; // separate blob
        sig.at(i, j, k, 0) = v;
      }
  Dwi dwi = makeDwi(sig, bvals, bvecs);
  MaskVolume m = automaticMask(dwi, 50.0);
  std::size_t inMask = 0;
  for (auto v : m.data)
    inMask += v;
  EXPECT_EQ(m.at(10, 10, 10), 1) << "the dark core is a hole and must be filled";
  EXPECT_EQ(m.at(21, 21, 3), 0) << "the separate blob is not the largest component";
  EXPECT_EQ(m.at(0, 0, 0), 0);
  EXPECT_EQ(inMask, ballVoxels);
}

namespace {

// The twoShell scheme's signal of one prolate tensor, S0 per voxel from `s0At(i, j, k)`, plus Gaussian noise
// of `sigma` (magnitude taken, as a scanner's).
template <class S0>
Dwi noisyPhantom(const Grid& grid, double sigma, S0 s0At, std::uint32_t seed) {
  const Scheme s = schemes()[1];
  const glm::dmat3 d(glm::dvec3(1.7e-3, 0, 0), glm::dvec3(0, 0.3e-3, 0), glm::dvec3(0, 0, 0.3e-3));
  const int n = static_cast<int>(s.bvals.size());
  Volume<float> v(grid, n);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (int k = 0; k < grid.dims.z; ++k)
    for (int j = 0; j < grid.dims.y; ++j)
      for (int i = 0; i < grid.dims.x; ++i) {
        const double s0 = s0At(i, j, k);
        for (int m = 0; m < n; ++m) {
          const glm::dvec3 g = glm::length(s.bvecs[m]) > 0 ? glm::normalize(s.bvecs[m]) : glm::dvec3(0);
          const double clean = s0 * std::exp(-s.bvals[m] * glm::dot(g, d * g));
          v.data[grid.index(i, j, k) * n + m] = static_cast<float>(std::abs(clean + noise(rng)));
        }
      }
  return makeDwi(v, s.bvals, s.bvecs);
}

// Captures the log's warnings while alive.
struct WarningLog {
  std::vector<std::string> warnings;
  WarningLog() {
    setLogSink([this](LogLevel l, const std::string& m) {
      if (l == LogLevel::Warning) warnings.push_back(m);
    });
  }
  ~WarningLog() { setLogSink({}); }
};

} // namespace

TEST(AutomaticMask, APhantomWithoutBackgroundKeepsEveryVoxel) {
  // A uniform phantom filling the grid (S0 1000, noise 2 %): Otsu alone splits its noise in two halves.
  const Grid grid = Grid::fromAffine({12, 12, 10}, glm::dmat4(1.0));
  const Dwi dwi = noisyPhantom(grid, 20.0, [](int, int, int) { return 1000.0; }, 3);
  AutomaticMaskReport report;
  const MaskVolume m = automaticMask(dwi, 50.0, &report);
  EXPECT_TRUE(report.noBackground);
  EXPECT_EQ(report.voxels, grid.voxelCount());
  EXPECT_EQ(report.signalVoxels, grid.voxelCount());
  EXPECT_EQ(report.kept, grid.voxelCount());
  EXPECT_EQ(std::count(m.data.begin(), m.data.end(), 1), static_cast<std::ptrdiff_t>(grid.voxelCount()));
  EXPECT_EQ(automaticMaskWarning(report), "");
  // The fit without --mask fits every voxel, and says nothing alarming.
  WarningLog log;
  FitStats stats;
  const TensorField f = fitTensors(dwi, nullptr, FitOptions{}, {}, &stats);
  EXPECT_EQ(stats.voxelsFitted, grid.voxelCount());
  EXPECT_EQ(std::count(f.valid.begin(), f.valid.end(), 1), static_cast<std::ptrdiff_t>(grid.voxelCount()));
  EXPECT_TRUE(log.warnings.empty());
}

TEST(AutomaticMask, APhantomInAirIsMaskedToItsBall) {
  // The same phantom as a ball of radius 5 in air (noise only): the air is background and goes.
  const Grid grid = Grid::fromAffine({16, 16, 16}, glm::dmat4(1.0));
  const auto inBall = [](int i, int j, int k) { return glm::length(glm::dvec3(i - 7.5, j - 7.5, k - 7.5)) <= 5; };
  const Dwi dwi = noisyPhantom(grid, 20.0, [&](int i, int j, int k) { return inBall(i, j, k) ? 1000.0 : 0.0; }, 4);
  AutomaticMaskReport report;
  const MaskVolume m = automaticMask(dwi, 50.0, &report);
  EXPECT_FALSE(report.noBackground);
  std::size_t ball = 0, wrong = 0;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i) {
        ball += inBall(i, j, k);
        wrong += (m.at(i, j, k) != 0) != inBall(i, j, k);
      }
  EXPECT_EQ(report.signalVoxels, ball);
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(automaticMaskWarning(report), "");
}

TEST(AutomaticMask, WarnsNamingTheMaskOptionWhenMostSignalIsDropped) {
  // Air in 3 of 16 columns, tissue of S0 300 in 9 and of S0 1000 in 4: 81 % of the voxels hold signal, too
  // few for "no background", and Otsu splits the bright tissue from the rest, keeping 4 of 13 columns.
  const Grid grid = Grid::fromAffine({16, 12, 10}, glm::dmat4(1.0));
  const Dwi dwi = noisyPhantom(grid, 5.0, [](int i, int, int) { return i < 3 ? 0.0 : i < 12 ? 300.0 : 1000.0; }, 5);
  AutomaticMaskReport report;
  automaticMask(dwi, 50.0, &report);
  EXPECT_FALSE(report.noBackground);
  EXPECT_EQ(report.signalVoxels, 13u * 12 * 10);
  EXPECT_EQ(report.keptSignal, 4u * 12 * 10);
  const std::string warning = automaticMaskWarning(report);
  EXPECT_NE(warning.find("keeps 480 of the 1560 voxels holding signal (31%)"), std::string::npos) << warning;
  EXPECT_NE(warning.find("--mask"), std::string::npos) << warning;
  // The fit logs it.
  WarningLog log;
  fitTensors(dwi, nullptr, FitOptions{});
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_EQ(log.warnings[0], warning);
}
