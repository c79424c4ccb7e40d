// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check (surfaces/analyses/orientation_check.h) on the real DWI and its corrupted tables, a
// re-strided (RAS) copy, the tensor files in their layouts, the DIPY crops and a small crop: the verdicts,
// the corrections, and the exactness of D' = G D G^T against a refit.
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "support/test_env.h"
#include "surfaces/analyses/orientation_check.h"
#include "support/volumes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <set>

namespace {

using namespace dtf;
using surfaces::AxisTransform;

AxisTransform fromRows(std::array<int, 9> m) {
  AxisTransform t;
  t.m = m;
  return t;
}

const AxisTransform kFlipX = fromRows({-1, 0, 0, 0, 1, 0, 0, 0, 1});
const AxisTransform kFlipY = fromRows({1, 0, 0, 0, -1, 0, 0, 0, 1});
const AxisTransform kFlipZ = fromRows({1, 0, 0, 0, 1, 0, 0, 0, -1});
const AxisTransform kSwapXY = fromRows({0, 1, 0, 1, 0, 0, 0, 0, 1});
const AxisTransform kSwapYZ = fromRows({1, 0, 0, 0, 0, 1, 0, 1, 0});
const AxisTransform kSwapXZ = fromRows({0, 0, 1, 0, 1, 0, 1, 0, 0});
const AxisTransform kCycle = fromRows({0, 1, 0, 0, 0, 1, 1, 0, 0}); // (x, y, z) -> (y, z, x)

std::vector<glm::dvec3> applyToTable(const std::vector<glm::dvec3>& bvecs, const AxisTransform& m) {
  std::vector<glm::dvec3> out;
  for (const auto& g : bvecs)
    out.push_back(m.apply(g));
  return out;
}

struct RealDwi {
  ScalarVolume signal;
  std::vector<double> bvals;
  std::vector<glm::dvec3> bvecs;
  MaskVolume mask;
};

RealDwi loadReal(const std::filesystem::path& dir) {
  RealDwi d;
  d.signal = io::readScalarVolume((dir / "dwi.nii.gz").string());
  d.bvals = io::readBvals((dir / "dwi.bval").string());
  d.bvecs = io::readBvecs((dir / "dwi.bvec").string());
  ScalarVolume m = io::readScalarVolume((dir / "derived" / "mask.nii.gz").string());
  d.mask = MaskVolume(m.grid, 1, 0);
  for (std::size_t i = 0; i < m.data.size(); ++i)
    d.mask.data[i] = m.data[i] != 0;
  return d;
}

TensorField fit(const ScalarVolume& signal, const std::vector<double>& bvals,
                const std::vector<glm::dvec3>& bvecs, const MaskVolume* mask,
                io::FitMethod method = io::FitMethod::Wls) {
  io::Dwi dwi = io::makeDwi(signal, bvals, bvecs);
  io::FitOptions o;
  o.method = method;
  o.threads = 2;
  return io::fitTensors(dwi, mask, o);
}

surfaces::OrientationReport check(const TensorField& field, const MaskVolume* mask = nullptr) {
  return surfaces::checkOrientation(field, io::bvecFrameToWorld(field.grid), mask);
}

void printReport(const char* what, const surfaces::OrientationReport& r) {
  std::printf("%-22s %-12s given %.4f best %.4f (%s) runner-up %s margin %.1f%% wm %zu\n", what,
              surfaces::verdictName(r.verdict), r.scoreGiven, r.scoreBest,
              r.candidates[r.best].transform.name().c_str(),
              r.candidates[r.runnerUp].transform.name().c_str(), 100 * r.margin, r.whiteMatterVoxels);
}

using test::flipI;

MaskVolume flipI(const MaskVolume& v) {
  ScalarVolume s(v.grid, 1);
  for (std::size_t i = 0; i < v.data.size(); ++i)
    s.data[i] = v.data[i];
  ScalarVolume f = flipI(s);
  MaskVolume out(f.grid, 1, 0);
  for (std::size_t i = 0; i < f.data.size(); ++i)
    out.data[i] = f.data[i] != 0;
  return out;
}

// FSL's bvec for a gradient given as voxel-frame components of `grid`: x negated when det(affine) > 0.
glm::dvec3 fslFromVoxel(const Grid& grid, glm::dvec3 g) {
  if (glm::determinant(glm::dmat3(grid.voxelToWorld)) > 0) g.x = -g.x;
  return g;
}
glm::dvec3 voxelFromFsl(const Grid& grid, const glm::dvec3& g) {
  return fslFromVoxel(grid, g);
}

TEST(OrientationCandidates, AreTheTwentyFourSignedPermutationsUpToSign) {
  const auto c = surfaces::orientationCandidates();
  ASSERT_EQ(c.size(), 24u);
  EXPECT_TRUE(c[0].isIdentity());
  // Every one of the 48 signed permutation matrices equals exactly one candidate up to sign.
  std::array<int, 3> perm{0, 1, 2};
  int all = 0;
  do {
    for (int s = 0; s < 8; ++s) {
      AxisTransform t;
      t.m.fill(0);
      for (int r = 0; r < 3; ++r)
        t.m[static_cast<std::size_t>(r * 3 + perm[r])] = (s >> r) & 1 ? -1 : 1;
      int matches = 0;
      for (const auto& k : c)
        matches += surfaces::sameUpToSign(t, k) ? 1 : 0;
      EXPECT_EQ(matches, 1) << t.name();
      ++all;
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  EXPECT_EQ(all, 48);
  std::set<std::string> names;
  for (const auto& k : c) {
    names.insert(k.name());
    EXPECT_TRUE(surfaces::compose(k, k.inverse()).isIdentity()) << k.name();
  }
  EXPECT_EQ(names.size(), 24u);
  EXPECT_EQ(kFlipX.name(), "-x y z");
  EXPECT_EQ(kCycle.name(), "y z x");
  EXPECT_EQ(kCycle.apply(glm::dvec3(1, 2, 3)), glm::dvec3(2, 3, 1));
}

class RealDwiCheck : public ::testing::Test {
protected:
  void SetUp() override {
    DTF_SHARED_FILE(dir, "iu_prisma_dwi/dwi.nii.gz");
    data_ = loadReal(dir.parent_path());
  }
  RealDwi data_;
};

// D' = G D G^T for the table M*g against a refit with that table: exact up to float storage, for WLS and
// OLS, on the LAS grid and on the RAS re-strided one (where G differs from M by the frame's x flip).
TEST_F(RealDwiCheck, TransformedFieldEqualsARefitWithThePermutedTable) {
  struct Grid2 {
    ScalarVolume signal;
    MaskVolume mask;
    std::vector<glm::dvec3> bvecs;
  };
  std::vector<Grid2> grids;
  grids.push_back({data_.signal, data_.mask, data_.bvecs});
  Grid2 ras{flipI(data_.signal), flipI(data_.mask), {}};
  for (const auto& g : data_.bvecs) {
    glm::dvec3 v = voxelFromFsl(data_.signal.grid, g);
    v.x = -v.x; // the reversed voxel axis i
    ras.bvecs.push_back(fslFromVoxel(ras.signal.grid, v));
  }
  grids.push_back(ras);
  for (const auto& gr : grids) {
    for (io::FitMethod method : {io::FitMethod::Wls, io::FitMethod::Ols}) {
      const TensorField base = fit(gr.signal, data_.bvals, gr.bvecs, &gr.mask, method);
      for (const AxisTransform& m : {kFlipX, kSwapYZ, kCycle, surfaces::compose(kSwapXY, kFlipZ)}) {
        const TensorField refit = fit(gr.signal, data_.bvals, applyToTable(gr.bvecs, m), &gr.mask, method);
        const TensorField turned = surfaces::transformedField(base, io::bvecFrameToWorld(gr.signal.grid), m);
        std::size_t n = 0, off = 0;
        double worst = 0;
        for (std::size_t i = 0; i < base.tensors.size(); ++i) {
          if (!base.valid[i]) continue;
          ASSERT_TRUE(refit.valid[i]);
          const auto a = refit.tensors[i].components(), b = turned.tensors[i].components();
          double diff = 0, norm = 0;
          for (int c = 0; c < 6; ++c) {
            diff = std::max(diff, double(std::abs(a[c] - b[c])));
            norm = std::max(norm, double(std::abs(a[c])));
          }
          // float storage: 1e-5 of the tensor's largest component.
          if (diff > 1e-5 * norm) ++off;
          worst = std::max(worst, diff / norm);
          ++n;
        }
        std::printf("%s %-8s %s: %zu of %zu voxels differ by more than 1e-5 relative (worst %.2g)\n",
                    gr.signal.grid.orientationCode().c_str(), m.name().c_str(),
                    method == io::FitMethod::Wls ? "WLS" : "OLS", off, n, worst);
        EXPECT_GT(n, 40000u);
        // Exact algebra, float storage: 1e-5. WLS solves normal equations whose weights S^2 span orders of
        // magnitude; in a voxel or two (of 49k) the rounding of the permuted system differs at 2e-4.
        const std::string what = gr.signal.grid.orientationCode() + " " + m.name() +
                                 (method == io::FitMethod::Wls ? " WLS" : " OLS");
        EXPECT_LE(off, method == io::FitMethod::Ols ? 0u : 5u) << what;
        EXPECT_LT(worst, 1e-3) << what;
      }
    }
  }
}

TEST_F(RealDwiCheck, TrueTableIsOkAndEveryCorruptionIsCorrectedBack) {
  const auto truth = check(fit(data_.signal, data_.bvals, data_.bvecs, &data_.mask), &data_.mask);
  printReport("true table", truth);
  EXPECT_EQ(truth.verdict, surfaces::Verdict::Ok) << truth.reason;
  EXPECT_TRUE(truth.correction.isIdentity());
  const std::vector<std::pair<const char*, AxisTransform>> corruptions{
      {"flip x", kFlipX},
      {"flip y", kFlipY},
      {"flip z", kFlipZ},
      {"swap x y", kSwapXY},
      {"swap y z", kSwapYZ},
      {"swap x z", kSwapXZ},
      {"cycle", kCycle},
      {"cycle^2", surfaces::compose(kCycle, kCycle)},
      {"swap x y + flip z", surfaces::compose(kFlipZ, kSwapXY)},
      {"cycle + flip x", surfaces::compose(kFlipX, kCycle)},
      {"flip x + flip y", surfaces::compose(kFlipX, kFlipY)},
  };
  for (const auto& [what, p] : corruptions) {
    const std::vector<glm::dvec3> bad = applyToTable(data_.bvecs, p);
    const auto r = check(fit(data_.signal, data_.bvals, bad, &data_.mask), &data_.mask);
    printReport(what, r);
    ASSERT_EQ(r.verdict, surfaces::Verdict::Corrected) << what << ": " << r.reason;
    // The correction restores the original table up to the sign of whole vectors.
    EXPECT_TRUE(surfaces::sameUpToSign(surfaces::compose(r.correction, p), AxisTransform{})) << what;
    const std::vector<glm::dvec3> fixed = applyToTable(bad, r.correction);
    for (std::size_t n = 0; n < fixed.size(); ++n)
      EXPECT_TRUE(fixed[n] == data_.bvecs[n] || fixed[n] == -data_.bvecs[n]) << what << " volume " << n;
    // The best table's score is the true table's: the same tensors up to a turn.
    EXPECT_NEAR(r.scoreBest, truth.scoreGiven, 1e-3 * truth.scoreGiven) << what;
  }
}

// The RAS copy with its FSL table re-exported by the rule (x negated when det > 0) is ok; the same copy with
// a table exported as if the data's x flip had to be copied into the table is caught as "-x y z".
TEST_F(RealDwiCheck, RestridedRasCopyIsOkAndItsNaiveTableIsCaught) {
  const ScalarVolume ras = flipI(data_.signal);
  const MaskVolume rasMask = flipI(data_.mask);
  ASSERT_GT(glm::determinant(glm::dmat3(ras.grid.voxelToWorld)), 0.0);
  EXPECT_EQ(ras.grid.orientationCode(), "RAS");
  std::vector<glm::dvec3> rasTable, naive;
  for (const auto& g : data_.bvecs) {
    glm::dvec3 v = voxelFromFsl(data_.signal.grid, g);
    v.x = -v.x;
    rasTable.push_back(fslFromVoxel(ras.grid, v));
    naive.push_back(glm::dvec3(-g.x, g.y, g.z));
  }
  // The world gradients agree between the two grids (the frame bookkeeping of io::makeDwi).
  const io::Dwi a = io::makeDwi(data_.signal, data_.bvals, data_.bvecs);
  const io::Dwi b = io::makeDwi(ras, data_.bvals, rasTable);
  for (std::size_t n = 0; n < a.gradientsWorld.size(); ++n)
    EXPECT_LT(glm::length(a.gradientsWorld[n] - b.gradientsWorld[n]), 1e-9) << n;

  const auto ok = check(fit(ras, data_.bvals, rasTable, &rasMask), &rasMask);
  printReport("RAS, FSL table", ok);
  EXPECT_EQ(ok.verdict, surfaces::Verdict::Ok) << ok.reason;
  const auto wrong = check(fit(ras, data_.bvals, naive, &rasMask), &rasMask);
  printReport("RAS, naive table", wrong);
  ASSERT_EQ(wrong.verdict, surfaces::Verdict::Corrected) << wrong.reason;
  EXPECT_TRUE(surfaces::sameUpToSign(wrong.correction, kFlipX)) << wrong.correction.name();
}

// Too little white matter is inconclusive, never corrected: 10x10x10 crops of the real brain, even with a
// corrupted table, including the crop through the corpus callosum.
TEST_F(RealDwiCheck, SmallCropsAreNeverCorrected) {
  const Grid& g = data_.signal.grid;
  int inconclusive = 0;
  for (const glm::ivec3 corner : {glm::ivec3(28, 37, 17), glm::ivec3(25, 29, 10), glm::ivec3(40, 40, 20)}) {
    Grid cg = Grid::fromAffine(glm::ivec3(10),
                               g.voxelToWorld * glm::translate(glm::dmat4(1.0), glm::dvec3(corner)));
    ScalarVolume crop(cg, data_.signal.components);
    for (int k = 0; k < 10; ++k)
      for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i)
          for (int c = 0; c < crop.components; ++c)
            crop.at(i, j, k, c) = data_.signal.at(corner.x + i, corner.y + j, corner.z + k, c);
    for (const AxisTransform& p : {AxisTransform{}, kFlipX}) {
      const auto r = check(fit(crop, data_.bvals, applyToTable(data_.bvecs, p), nullptr));
      printReport(p.isIdentity() ? "10^3 crop" : "10^3 crop, flip x", r);
      EXPECT_NE(r.verdict, surfaces::Verdict::Corrected);
      inconclusive += r.verdict == surfaces::Verdict::Inconclusive ? 1 : 0;
    }
  }
  EXPECT_EQ(inconclusive, 6);
}

TEST(OrientationCheckTensorFiles, WrongLayoutAndFrameAreFlagged) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/dti_tensor_mrtrix.nii.gz");
  const glm::dmat3 world(1.0);
  const auto asFsl = surfaces::checkOrientation(io::readTensorVolume(fsl.string()).field, world);
  printReport("FSL file (auto)", asFsl);
  EXPECT_EQ(asFsl.verdict, surfaces::Verdict::Ok) << asFsl.reason;
  const auto asMrtrix = surfaces::checkOrientation(io::readTensorVolume(mrtrix.string()).field, world);
  printReport("MRtrix file (auto)", asMrtrix);
  EXPECT_EQ(asMrtrix.verdict, surfaces::Verdict::Ok) << asMrtrix.reason;

  const auto misread =
      surfaces::checkOrientation(io::readTensorVolume(fsl.string(), io::TensorLayout::Mrtrix).field, world);
  printReport("FSL file as MRtrix", misread);
  EXPECT_NE(misread.verdict, surfaces::Verdict::Ok) << misread.reason;

  // The MRtrix file with its x row negated (xy and xz change sign: D -> F D F, F = diag(-1, 1, 1)).
  TensorField negated = io::readTensorVolume(mrtrix.string()).field;
  for (auto& t : negated.tensors) {
    t.xy = -t.xy;
    t.xz = -t.xz;
  }
  const auto flipped = surfaces::checkOrientation(negated, world);
  printReport("MRtrix, x row negated", flipped);
  ASSERT_EQ(flipped.verdict, surfaces::Verdict::Corrected) << flipped.reason;
  EXPECT_TRUE(surfaces::sameUpToSign(flipped.correction, kFlipX)) << flipped.correction.name();
}

TEST(OrientationCheckDipyCrops, AreOkOrInconclusiveNeverCorrected) {
  DTF_SHARED_FILE(dir, "dipy_small/small_64D.nii");
  for (const char* name : {"small_64D", "small_101D"}) {
    const auto base = dir.parent_path() / name;
    const std::string nii =
        std::filesystem::exists(base.string() + ".nii") ? base.string() + ".nii" : base.string() + ".nii.gz";
    const io::Dwi dwi = io::readDwi(nii, base.string() + ".bval", base.string() + ".bvec");
    io::FitOptions o;
    const TensorField field = io::fitTensors(dwi, nullptr, o);
    const auto r = check(field);
    printReport(name, r);
    EXPECT_NE(r.verdict, surfaces::Verdict::Corrected) << name << ": " << r.reason;
  }
}

TEST(OrientationCheck, MaskOnAnotherGridIsRefused) {
  const TensorField f = makeTensorField(Grid::fromAffine(glm::ivec3(4), glm::dmat4(1.0)));
  const MaskVolume m(Grid::fromAffine(glm::ivec3(5), glm::dmat4(1.0)), 1, 1);
  EXPECT_THROW(surfaces::checkOrientation(f, glm::dmat3(1.0), &m), dtf::InputError);
}

} // namespace

namespace {

// The thresholds against sub-blocks of the real brain (the fit is per voxel, so a block of the fitted field
// is the fit of that block of the DWI; the scores are equivariant, so a block that picks a wrong table
// under the true one would pick a wrong correction under any corrupted one).
TEST_F(RealDwiCheck, ThresholdsHoldOnSubBlocksOfTheRealBrain) {
  const TensorField full = fit(data_.signal, data_.bvals, data_.bvecs, &data_.mask);
  const Grid& g = full.grid;
  const surfaces::CheckOptions defaults;
  std::size_t blocks = 0, decided = 0, wrongDecided = 0, wrongBelowCount = 0, wrongBelowMargin = 0;
  std::size_t smallestDecided = SIZE_MAX;
  double largestWrongMargin = 0, largeWrongMargin = 0, smallestDecidedMargin = 1e9;
  std::size_t largestWrongWm = 0;
  for (int size : {10, 14, 18, 24, 30, 36}) {
    for (int k0 = 0; k0 + size <= g.dims.z; k0 += std::max(3, size / 2))
      for (int j0 = 0; j0 + size <= g.dims.y; j0 += size / 2)
        for (int i0 = 0; i0 + size <= g.dims.x; i0 += size / 2) {
          const glm::ivec3 dims(size, size, std::min(size, g.dims.z));
          Grid cg = Grid::fromAffine(dims, g.voxelToWorld *
                                               glm::translate(glm::dmat4(1.0), glm::dvec3(i0, j0, k0)));
          TensorField crop = makeTensorField(cg);
          for (int k = 0; k < dims.z; ++k)
            for (int j = 0; j < dims.y; ++j)
              for (int i = 0; i < dims.x; ++i) {
                const std::size_t src = g.index(i0 + i, j0 + j, k0 + k), dst = cg.index(i, j, k);
                crop.tensors[dst] = full.tensors[src];
                crop.valid[dst] = full.valid[src];
              }
          surfaces::CheckOptions anything = defaults;
          anything.minWhiteMatter = 1;
          anything.minMargin = 0;
          const auto r = surfaces::checkOrientation(crop, io::bvecFrameToWorld(cg), nullptr, anything);
          if (r.whiteMatterVoxels < 50) continue;
          ++blocks;
          const bool wrong = r.best != 0;
          const bool passes =
              r.whiteMatterVoxels >= defaults.minWhiteMatter && r.margin >= defaults.minMargin;
          if (wrong) {
            largestWrongMargin = std::max(largestWrongMargin, r.margin);
            largestWrongWm = std::max(largestWrongWm, r.whiteMatterVoxels);
            if (r.whiteMatterVoxels >= 1000) largeWrongMargin = std::max(largeWrongMargin, r.margin);
            if (r.whiteMatterVoxels < defaults.minWhiteMatter)
              ++wrongBelowCount;
            else if (r.margin < defaults.minMargin)
              ++wrongBelowMargin;
          }
          if (passes) {
            ++decided;
            smallestDecided = std::min(smallestDecided, r.whiteMatterVoxels);
            smallestDecidedMargin = std::min(smallestDecidedMargin, r.margin);
            wrongDecided += wrong ? 1 : 0;
          }
        }
  }
  std::printf(
      "sub-blocks: %zu with >= 50 white-matter voxels; wrong best table in %zu below %zu voxels and %zu "
      "above it below a %.0f%% margin (largest wrong: margin %.1f%%, %zu voxels); %zu pass both thresholds "
      "(smallest %zu voxels, smallest margin %.1f%%), %zu of them wrong; largest margin of a wrong block "
      "with >= 1000 voxels %.1f%%\n",
      blocks, wrongBelowCount, defaults.minWhiteMatter, wrongBelowMargin, 100 * defaults.minMargin,
      100 * largestWrongMargin, largestWrongWm, decided, smallestDecided, 100 * smallestDecidedMargin,
      wrongDecided, 100 * largeWrongMargin);
  EXPECT_GT(decided, 20u);
  EXPECT_EQ(wrongDecided, 0u);
  // Each threshold alone excludes every wrong block of 1000 or more white-matter voxels: the count (no wrong
  // block reaches it) and the margin (no wrong block of that size leads by as much).
  EXPECT_LT(largestWrongWm, defaults.minWhiteMatter);
  EXPECT_LT(largeWrongMargin, defaults.minMargin);
}

} // namespace
