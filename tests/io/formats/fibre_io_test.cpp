// SPDX-License-Identifier: GPL-3.0-or-later
// FibreSet (io/model/fibre_set.h) and the fibre readers/writers (io/formats/fibre_io.h): the lobe-matching
// interpolation against closed-form cases, phantom round trips through every layout on RAS and LAS grids,
// and the real brain's MRtrix, DIPY and bedpostx files against the reference voxels of the data README.
#include "io/formats/fibre_io.h"
#include "io/model/error.h"
#include "io/phantoms.h"
#include "support/test_env.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace dtf;

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::vec3 dir(double deg) {
  return {float(std::cos(deg * kPi / 180)), float(std::sin(deg * kPi / 180)), 0.0f};
}

double angleDeg(glm::vec3 a, glm::vec3 b) {
  return std::acos(std::min(1.0, std::abs(double(glm::dot(glm::normalize(a), glm::normalize(b)))))) * 180 /
         kPi;
}

FibreSet twoByTwo() {
  Grid g = Grid::fromAffine({2, 2, 2}, glm::dmat4(1.0));
  return makeFibreSet(g, 3);
}

} // namespace

TEST(FibreInterpolation, MatchesLobesAcrossOrderAndSign) {
  // Every voxel holds the same two fibres (20 and 110 degrees) in varying order and sign: per-component
  // interpolation would tear them, lobe matching must give both back exactly.
  FibreSet s = twoByTwo();
  for (int c = 0; c < 8; ++c) {
    Fibre* f = s.at(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const float sa = (c % 3 == 0) ? -1.0f : 1.0f, sb = (c % 2 == 0) ? -1.0f : 1.0f;
    const bool swap = c % 2 == 1;
    f[swap ? 1 : 0] = {sa * dir(20), 0.6f};
    f[swap ? 0 : 1] = {sb * dir(110), 0.5f};
  }
  normaliseFibres(s);
  for (glm::dvec3 p : {glm::dvec3(0.5), glm::dvec3(0.2, 0.7, 0.4), glm::dvec3(0.9, 0.1, 0.6)}) {
    auto out = interpolateFibres(s, p, 0.1f);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_LT(angleDeg(out[0].direction, dir(20)), 1e-3);
    EXPECT_LT(angleDeg(out[1].direction, dir(110)), 1e-3);
    EXPECT_NEAR(out[0].amplitude, 0.6f, 1e-5);
    EXPECT_NEAR(out[1].amplitude, 0.5f, 1e-5);
  }
}

TEST(FibreInterpolation, ThresholdDropsWeakLobesAndBlendsDirections) {
  FibreSet s = twoByTwo();
  for (int c = 0; c < 8; ++c) {
    Fibre* f = s.at(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    // x = 0 voxels point at 0 degrees, x = 1 voxels at 20 degrees; a weak 90-degree lobe everywhere.
    f[0] = {(c & 1) ? dir(20) : -dir(0), 1.0f};
    f[1] = {dir(90), 0.05f};
  }
  auto out = interpolateFibres(s, glm::dvec3(0.5, 0.5, 0.5), 0.1f);
  ASSERT_EQ(out.size(), 1u); // 0.05 < 0.1 x 1.0: dropped
  EXPECT_LT(angleDeg(out[0].direction, dir(10)), 0.01);
  auto low = interpolateFibres(s, glm::dvec3(0.5, 0.5, 0.5), 0.01f);
  ASSERT_EQ(low.size(), 2u);
  EXPECT_LT(angleDeg(low[1].direction, dir(90)), 1e-3);
  // Naive per-component averaging of the signed vectors would cancel (0 and 180 degrees): the matched
  // amplitude stays the full one.
  EXPECT_NEAR(out[0].amplitude, 1.0f, 1e-5);
}

TEST(FibreInterpolation, EmptyWhereLessThanHalfTheWeightHasFibres) {
  FibreSet s = twoByTwo();
  s.at(0, 0, 0)[0] = {dir(0), 1.0f};
  EXPECT_TRUE(interpolateFibres(s, glm::dvec3(0.5), 0.1f).empty());
  EXPECT_EQ(interpolateFibres(s, glm::dvec3(0.0), 0.1f).size(), 1u);
}

TEST(FibreInterpolation, MutualBestKeepsACrossingBundleStraightWhereTheOtherEnds) {
  // Reference voxel (weight 0.7) holds 0 and 60 degrees; its x neighbour only 0 degrees. The neighbour's
  // lobe is within 60 degrees of both reference lobes but belongs to the 0-degree one.
  FibreSet s = twoByTwo();
  for (int c = 0; c < 8; ++c) {
    Fibre* f = s.at(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    f[0] = {dir(0), 1.0f};
    if (!(c & 1)) f[1] = {dir(60), 0.9f};
  }
  auto out = interpolateFibres(s, glm::dvec3(0.3, 0.5, 0.5), 0.1f);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_LT(angleDeg(out[1].direction, dir(60)), 1e-3);
  EXPECT_NEAR(out[1].amplitude, 0.9f * 0.7f, 1e-5); // the 0.3 weight of voxels without it
}

TEST(FibreSlots, ContinuousSlotsFollowBundlesWhereStrengthOrderFlips) {
  io::PhantomOptions o;
  o.size = 20;
  o.crossingDeg = 80;
  FibreSet f = io::makeFibrePhantom("crossing", o); // overlap voxels list the bundles in alternating order
  FibreSet s = continuousSlots(f);
  ASSERT_EQ(s.maxFibres, 2);
  const glm::vec3 d1 = dir(-40), d2 = dir(40);
  // In every voxel with both bundles, the bundle in slot 0 is the same as in its x neighbour's slot 0.
  std::size_t both = 0, agree = 0;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 1; i < 20; ++i) {
        const Fibre* a = s.at(i, j, k);
        const Fibre* b = s.at(i - 1, j, k);
        if (!(a[0].amplitude > 0 && a[1].amplitude > 0 && b[0].amplitude > 0 && b[1].amplitude > 0)) continue;
        ++both;
        agree += angleDeg(a[0].direction, b[0].direction) < 1.0;
      }
  EXPECT_GT(both, 50u);
  EXPECT_EQ(agree, both);
  // The raw set flips: slot 0 alternates between the bundles.
  std::size_t flips = 0;
  for (int i = 1; i < 20; ++i) {
    const Fibre* a = f.at(i, 10, 10);
    const Fibre* b = f.at(i - 1, 10, 10);
    if (a[1].amplitude > 0 && b[1].amplitude > 0) flips += angleDeg(a[0].direction, b[0].direction) > 10;
  }
  EXPECT_GT(flips, 0u);
  (void)d1;
  (void)d2;
}

TEST(FibreSlots, SlotInterpolationAgreesWithPerPointLobeMatching) {
  // The renderer matches lobes once per voxel pair (continuousSlots) and interpolates slots per component;
  // away from seams this must give what matching at every point (interpolateFibres) gives.
  for (double crossing : {60.0, 90.0}) {
    io::PhantomOptions o;
    o.size = 24;
    o.crossingDeg = crossing;
    o.las = crossing == 90.0;
    FibreSet f = io::makeFibrePhantom("crossing", o);
    FibreSet s = continuousSlots(f, 0.15f);
    std::size_t points = 0, agree = 0;
    for (double z = 10.2; z < 14; z += 1.3)
      for (double y = 1.3; y < 22; y += 0.7)
        for (double x = 1.1; x < 22; x += 0.7) {
          auto ref = interpolateFibres(f, {x, y, z}, 0.15f);
          auto slot = interpolateSlots(s, {x, y, z});
          std::vector<Fibre> present;
          for (const Fibre& p : slot)
            if (p.amplitude > 0) present.push_back(p);
          if (ref.empty() && present.empty()) continue;
          ++points;
          if (ref.size() != present.size()) continue;
          bool ok = true;
          for (const Fibre& r : ref) {
            double best = 180;
            for (const Fibre& p : present)
              if (std::abs(p.amplitude - r.amplitude) < 0.02)
                best = std::min(best, angleDeg(p.direction, r.direction));
            ok = ok && best < 1.0;
          }
          agree += ok;
        }
    EXPECT_GT(points, 1000u);
    // The rest lie along slot seams (where bundles entered the scan separately and meet): there slot
    // interpolation mixes two bundles, turning from one to the other.
    EXPECT_GT(double(agree), 0.9 * double(points)) << crossing;
  }
}

TEST(FibreSlots, InterpolationTurnsContinuouslyWhereVoxelsDisagree) {
  // One slot; along x the voxels hold directions 80 degrees apart with opposite signs (grey matter's noisy
  // directions, a seam of the sign alignment). The slot's direction must turn smoothly from one to the other
  // and keep the axis exactly between voxels that agree up to sign: no jump at the half-voxel boundary.
  Grid g = Grid::fromAffine({4, 1, 1}, glm::dmat4(1.0));
  FibreSet s = makeFibreSet(g, 1);
  const glm::vec3 axes[4] = {dir(0), -dir(80), dir(80), -dir(80)};
  for (int i = 0; i < 4; ++i)
    s.at(i, 0, 0)[0] = {axes[i], 1.0f};
  double prev = -1, largestStep = 0, first = 0, last = 0;
  for (double x = 0.0; x <= 1.0 + 1e-9; x += 0.01) {
    const auto f = interpolateSlots(s, {x, 0, 0});
    ASSERT_EQ(f.size(), 1u);
    ASSERT_GT(f[0].amplitude, 0.0f);
    EXPECT_NEAR(f[0].amplitude, 1.0f, 1e-5f);
    const double a = angleDeg(f[0].direction, dir(0));
    if (prev >= 0) largestStep = std::max(largestStep, std::abs(a - prev));
    if (x == 0.0) first = a;
    last = a;
    prev = a;
  }
  EXPECT_NEAR(first, 0.0, 1e-3);
  EXPECT_NEAR(last, 80.0, 1e-3);
  EXPECT_LT(largestStep, 6.0); // 80 degrees over 100 steps, faster in the middle (3.2 at most): never a jump
  // Between voxels 1 and 2 (the same axis, opposite signs) the axis holds throughout.
  for (double x = 1.0; x <= 2.0 + 1e-9; x += 0.05)
    EXPECT_LT(angleDeg(interpolateSlots(s, {x, 0, 0})[0].direction, dir(80)), 1e-3) << x;
}

TEST(FibreSlots, SignsAreAlignedBetweenNeighbours) {
  io::PhantomOptions o;
  o.size = 20;
  FibreSet s =
      continuousSlots(io::makeFibrePhantom("crossing", o)); // the phantom flips signs every 3rd voxel
  std::size_t pairs = 0, aligned = 0;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 1; i < 20; ++i)
        for (int n = 0; n < 2; ++n) {
          const Fibre& a = s.at(i, j, k)[n];
          const Fibre& b = s.at(i - 1, j, k)[n];
          // Same bundle in the slot on both sides (slot seams aside): then the same sign.
          if (!(a.amplitude > 0 && b.amplitude > 0) || std::abs(glm::dot(a.direction, b.direction)) < 0.99f)
            continue;
          ++pairs;
          aligned += glm::dot(a.direction, b.direction) > 0.99f;
        }
  EXPECT_GT(pairs, 500u);
  EXPECT_EQ(aligned, pairs);
}

TEST(FibreIo, PhantomRoundTripsThroughEveryLayoutOnRasAndLas) {
  for (bool las : {false, true})
    for (double crossing : {60.0, 90.0}) {
      io::PhantomOptions o;
      o.size = 24;
      o.crossingDeg = crossing;
      o.las = las;
      FibreSet ref = io::makeFibrePhantom("crossing", o);
      EXPECT_EQ(ref.grid.orientationCode(), las ? "LAS" : "RAS");
      for (io::FibreLayout l :
           {io::FibreLayout::MrtrixPeaks, io::FibreLayout::DipyPeaks, io::FibreLayout::Bedpostx}) {
        const auto dirPath =
            test::scratchDir() / (std::string(io::fibreLayoutName(l)) + (las ? "_las" : "_ras"));
        const std::string path =
            l == io::FibreLayout::Bedpostx ? dirPath.string() : dirPath.string() + ".nii.gz";
        io::writeFibres(path, ref, l);
        std::string why;
        EXPECT_TRUE(io::looksLikeFibres(path, &why)) << why;
        io::LoadedFibres back = io::readFibres(path);
        EXPECT_EQ(back.layout, l) << back.layoutReason;
        ASSERT_EQ(back.set.grid.dims, ref.grid.dims);
        std::size_t compared = 0;
        for (std::size_t v = 0; v < ref.grid.voxelCount(); ++v)
          for (int n = 0; n < 2; ++n) {
            const Fibre& a = ref.fibres[v * 2 + static_cast<std::size_t>(n)];
            if (!(a.amplitude > 0)) continue;
            // Same world direction (up to sign) in some slot of the read voxel, same amplitude.
            double best = 180;
            float amp = 0;
            for (int m = 0; m < back.set.maxFibres; ++m) {
              const Fibre& b =
                  back.set
                      .fibres[v * static_cast<std::size_t>(back.set.maxFibres) + static_cast<std::size_t>(m)];
              if (b.amplitude > 0 && angleDeg(a.direction, b.direction) < best) {
                best = angleDeg(a.direction, b.direction);
                amp = b.amplitude;
              }
            }
            ASSERT_LT(best, 0.01) << io::fibreLayoutName(l) << " voxel " << v;
            EXPECT_NEAR(amp, a.amplitude, 1e-5);
            ++compared;
          }
        EXPECT_GT(compared, 100u);
        // Read with the other frame: on LAS every oblique direction comes back mirrored in x.
        if (l != io::FibreLayout::Bedpostx && las) {
          io::LoadedFibres wrong =
              io::readFibres(path, l == io::FibreLayout::MrtrixPeaks ? io::FibreLayout::DipyPeaks
                                                                     : io::FibreLayout::MrtrixPeaks);
          const glm::vec3 d = wrong.set.at(12, 12, 12)[0].direction, r = ref.at(12, 12, 12)[0].direction;
          EXPECT_GT(angleDeg(d, r), 30.0);
        }
      }
    }
}

TEST(FibreIo, SixVolumePeaksAreNotReadAsATensor) {
  io::PhantomOptions o;
  o.size = 20;
  FibreSet f = io::makeFibrePhantom("crossing", o);
  const auto path = (test::scratchDir() / "two_peaks.nii.gz").string();
  io::writeFibres(path, f, io::FibreLayout::DipyPeaks);
  try {
    io::readTensorVolume(path);
    FAIL() << "two peaks read as a tensor";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no tensor but two fibre peaks"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST(FibreIo, RealBrainLayoutsAgreeAndMatchTheReferenceVoxels) {
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  DTF_SHARED_FILE(dipy, "iu_prisma_dwi/derived/fibres/peaks_dipy.nii.gz");
  DTF_SHARED_FILE(dyads, "iu_prisma_dwi/derived/fibres/bedpostx_layout/dyads1.nii.gz");
  io::LoadedFibres m = io::readFibres(mrtrix.string()), d = io::readFibres(dipy.string());
  io::LoadedFibres b = io::readFibres(dyads.string()), bf = io::readFibres(dyads.parent_path().string());
  // Neither peaks file records its frame: fibre coherence must pick world for MRtrix, voxel for DIPY.
  EXPECT_EQ(m.layout, io::FibreLayout::MrtrixPeaks) << m.layoutReason;
  EXPECT_EQ(d.layout, io::FibreLayout::DipyPeaks) << d.layoutReason;
  EXPECT_NE(m.layoutReason.find("coherence"), std::string::npos) << m.layoutReason;
  EXPECT_EQ(b.layout, io::FibreLayout::Bedpostx);
  EXPECT_EQ(m.set.maxFibres, 3);
  EXPECT_EQ(b.set.maxFibres, 3);
  // Reference voxels (data README): CC (33,42,22) MRtrix first peak unit (0.957, -0.070, 0.275) world,
  // length |(1.506, -0.111, 0.433)|; CST (30,34,15) MRtrix (0.378, -0.151, 1.169), DIPY voxel (-0.272,
  // -0.068, 0.960).
  const Fibre& cc = m.set.at(33, 42, 22)[0];
  EXPECT_LT(angleDeg(cc.direction, {0.957f, -0.070f, 0.275f}), 0.5);
  EXPECT_GT(cc.direction.x, 0.9f); // red: left-right
  EXPECT_NEAR(cc.amplitude, glm::length(glm::vec3(1.506f, -0.111f, 0.433f)), 2e-3);
  EXPECT_LT(angleDeg(d.set.at(33, 42, 22)[0].direction, {0.951f, -0.122f, 0.283f}), 0.5);
  EXPECT_LT(angleDeg(m.set.at(30, 34, 15)[0].direction, {0.378f, -0.151f, 1.169f}), 0.5);
  EXPECT_LT(angleDeg(d.set.at(30, 34, 15)[0].direction, {0.272f, -0.068f, 0.960f}), 0.5);
  EXPECT_GT(std::abs(d.set.at(30, 34, 15)[0].direction.z), 0.9f); // blue: superior-inferior
  // bedpostx here is converted from DIPY: same directions, folder or file.
  std::size_t same = 0, both = 0;
  std::vector<double> cosMd;
  for (std::size_t v = 0; v < d.set.grid.voxelCount(); ++v) {
    const Fibre& a = d.set.fibres[v * 3];
    const Fibre& c = b.set.fibres[v * 3];
    const Fibre& c2 = bf.set.fibres[v * 3];
    const Fibre& mm = m.set.fibres[v * 3];
    if (a.amplitude > 0 && c.amplitude > 0) {
      ++both;
      same += angleDeg(a.direction, c.direction) < 0.1 && angleDeg(c.direction, c2.direction) < 1e-6;
    }
    if (a.amplitude > 0 && mm.amplitude > 0) cosMd.push_back(std::abs(glm::dot(a.direction, mm.direction)));
  }
  EXPECT_GT(both, 10000u);
  // (bedpostx is ordered by its fractions, DIPY by slot: a few voxels with near-equal peaks swap.)
  EXPECT_GT(double(same), 0.995 * double(both));
  ASSERT_GT(cosMd.size(), 10000u);
  std::nth_element(cosMd.begin(), cosMd.begin() + std::ptrdiff_t(cosMd.size() / 2), cosMd.end());
  EXPECT_GT(cosMd[cosMd.size() / 2], 0.98); // README: median |cos| 0.993 after the frame change
}

TEST(FibreIo, MalformedFilesFailNamingTheFileAndTheProblem) {
  const auto dir = test::scratchDir();
  Grid g = Grid::fromAffine({4, 4, 4}, glm::dmat4(1.0));
  auto expectError = [&](const std::string& path, const std::string& what) {
    try {
      io::readFibres(path, io::FibreLayout::MrtrixPeaks);
      ADD_FAILURE() << "no error for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  ScalarVolume v(g, 6, 0.0f);
  v.data[0] = 1.0f;
  v.data[1] = std::nanf("");
  io::writeScalarVolume((dir / "partnan.nii").string(), v);
  expectError((dir / "partnan.nii").string(), "partly NaN");
  v.data[1] = INFINITY;
  io::writeScalarVolume((dir / "inf.nii").string(), v);
  expectError((dir / "inf.nii").string(), "Inf");
  ScalarVolume z(g, 6, 0.0f);
  io::writeScalarVolume((dir / "zero.nii").string(), z);
  expectError((dir / "zero.nii").string(), "no fibre direction");
  ScalarVolume w(g, 7, 0.5f);
  io::writeScalarVolume((dir / "seven.nii").string(), w);
  expectError((dir / "seven.nii").string(), "multiple of 3");
  // bedpostx: fractions on another grid, and a missing fractions file.
  const auto bp = dir / "bp";
  std::filesystem::create_directories(bp);
  ScalarVolume dy(g, 3, 0.0f);
  dy.data[0] = 1.0f;
  io::writeScalarVolume((bp / "dyads1.nii.gz").string(), dy);
  try {
    io::readFibres(bp.string());
    ADD_FAILURE() << "no error for a missing fractions file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mean_f1samples"), std::string::npos) << e.what();
  }
  ScalarVolume fr(Grid::fromAffine({5, 4, 4}, glm::dmat4(1.0)), 1, 0.5f);
  io::writeScalarVolume((bp / "mean_f1samples.nii.gz").string(), fr);
  try {
    io::readFibres((bp / "dyads1.nii.gz").string());
    ADD_FAILURE() << "no error for mismatched grids";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grid differs"), std::string::npos) << e.what();
  }
}
