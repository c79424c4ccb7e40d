// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check on fibre sets (surfaces::checkFibreOrientation): synthetic tubes whose frame is
// known in closed form, then the real Prisma peaks in each layout, right and wrong.
#include "io/formats/fibre_io.h"
#include "io/model/error.h"
#include "io/model/tensor_field.h"
#include "io/formats/tensor_io.h"
#include "support/test_env.h"
#include "surfaces/analyses/orientation_check.h"

#include <gtest/gtest.h>

namespace {

using dtf::Fibre;
using dtf::FibreSet;
using dtf::Grid;
using dtf::surfaces::AxisTransform;
using dtf::surfaces::checkFibreOrientation;
using dtf::surfaces::Verdict;

AxisTransform named(std::array<int, 9> m) {
  AxisTransform t;
  t.m = m;
  return t;
}

// An LAS grid (x negated: voxel frame and world differ by the sign of x) holding one-voxel-thick straight
// tubes along oblique voxel diagonals, each voxel's single fibre along its tube in world RAS, turned by
// `turn` (a file whose directions are off by `turn`). Besides the tubes: voxels with two equal fibres
// (crossings / noise: not dominant) and voxels with one weak fibre (below the median amplitude); neither
// may count as white matter.
struct Tubes {
  FibreSet set;
  std::size_t tubeVoxels = 0;
};

Tubes makeTubes(const glm::dmat3& turn) {
  Grid g;
  g.dims = {40, 40, 40};
  g.voxelToWorld = glm::dmat4(1.0);
  g.voxelToWorld[0][0] = -2.0;
  g.voxelToWorld[1][1] = 2.0;
  g.voxelToWorld[2][2] = 2.0;
  Tubes t;
  t.set = dtf::makeFibreSet(g, 2);
  const glm::dmat3 linear(g.voxelToWorld);
  const std::array<glm::ivec3, 4> dirs{glm::ivec3(1, 1, 0), glm::ivec3(0, 1, 1), glm::ivec3(1, 0, 1),
                                       glm::ivec3(1, -1, 1)};
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const glm::ivec3 o = dirs[static_cast<std::size_t>((a + b) % 4)];
      const glm::dvec3 w = turn * glm::normalize(linear * glm::dvec3(o));
      // A tube from a start on a coarse lattice, stepping along o while inside.
      glm::ivec3 p(4 + 8 * a, 4 + 8 * b, o.z != 0 ? 2 : 4 + 4 * ((a + b) % 8));
      if (o.y < 0) p.y = 38;
      for (; g.contains(p.x, p.y, p.z); p += o) {
        Fibre* f = t.set.at(p.x, p.y, p.z);
        if (f[0].amplitude > 0) continue;
        f[0].direction = glm::vec3(w);
        f[0].amplitude = 1.0f;
        ++t.tubeVoxels;
      }
    }
  // Noise in the empty voxels: alternately two equal fibres and one weak fibre, directions varying.
  std::size_t n = 0;
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        Fibre* f = t.set.at(i, j, k);
        if (f[0].amplitude > 0 || (i + 2 * j + 3 * k) % 5 != 0) continue;
        const glm::vec3 d = glm::normalize(glm::vec3(std::sin(0.7f * i + k), std::cos(1.3f * j), 0.5f));
        f[0] = {d, ++n % 2 ? 0.5f : 0.1f};
        if (n % 2) f[1] = {glm::normalize(glm::vec3(d.y, -d.x, 0.2f)), 0.45f};
      }
  dtf::normaliseFibres(t.set);
  return t;
}

dtf::surfaces::CheckOptions smallOptions() {
  dtf::surfaces::CheckOptions o;
  o.minWhiteMatter = 100;
  return o;
}

TEST(FibreOrientationCheck, WorldFrameTubesAreOkAndOnlyTheTubesAreWhiteMatter) {
  const Tubes t = makeTubes(glm::dmat3(1.0));
  const auto r = checkFibreOrientation(t.set, glm::dmat3(1.0), nullptr, nullptr, smallOptions());
  EXPECT_EQ(r.verdict, Verdict::Ok) << r.reason;
  EXPECT_TRUE(r.correction.isIdentity());
  EXPECT_EQ(r.whiteMatterVoxels, t.tubeVoxels) << r.whiteMatterRule;
  EXPECT_GT(r.maskVoxels, 2 * t.tubeVoxels);
  EXPECT_GT(r.margin, 0.5);
}

TEST(FibreOrientationCheck, DirectionsReadInTheWrongFrameAreCorrectedBack) {
  // Off by an x flip (a voxel-frame file read as world on this LAS grid) and by an x/y swap.
  for (const AxisTransform& off : {named({-1, 0, 0, 0, 1, 0, 0, 0, 1}), named({0, 1, 0, 1, 0, 0, 0, 0, 1})}) {
    const Tubes t = makeTubes(off.matrix());
    const auto r = checkFibreOrientation(t.set, glm::dmat3(1.0), nullptr, nullptr, smallOptions());
    EXPECT_EQ(r.verdict, Verdict::Corrected) << off.name() << ": " << r.reason;
    EXPECT_TRUE(dtf::surfaces::sameUpToSign(r.correction, off.inverse()))
        << off.name() << ": " << r.correction.name();
  }
}

TEST(FibreOrientationCheck, CandidatesActOnTheStoredFrame) {
  // Stored in the voxel frame R^T d (read as voxel frame: world = R * stored): right, so ok.
  const Tubes right = makeTubes(glm::dmat3(1.0));
  const glm::dmat3 rotation = right.set.grid.rotation();
  auto r = checkFibreOrientation(right.set, rotation, nullptr, nullptr, smallOptions());
  EXPECT_EQ(r.verdict, Verdict::Ok) << r.reason;
  // World-frame directions read as voxel frame: the reader turned them by R; the correction in the stored
  // frame is R^T = the x flip.
  const Tubes turned = makeTubes(rotation);
  r = checkFibreOrientation(turned.set, rotation, nullptr, nullptr, smallOptions());
  EXPECT_EQ(r.verdict, Verdict::Corrected) << r.reason;
  EXPECT_EQ(r.correction, named({-1, 0, 0, 0, 1, 0, 0, 0, 1})) << r.correction.name();
}

TEST(FibreOrientationCheck, GridMismatchIsAnInputError) {
  const Tubes t = makeTubes(glm::dmat3(1.0));
  dtf::MaskVolume mask(Grid{}, 1, 1);
  EXPECT_THROW(checkFibreOrientation(t.set, glm::dmat3(1.0), &mask), dtf::InputError);
}

// The real peaks: each file in its own layout is ok; the DIPY (voxel frame) file read as world-frame MRtrix
// peaks and the MRtrix file read as DIPY are corrected with the x flip (LAS grid), with or without FA.
TEST(FibreOrientationCheckData, RealPeaksInTheirLayoutAreOkAndMisreadOnesGetTheXFlip) {
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  DTF_SHARED_FILE(dipy, "iu_prisma_dwi/derived/fibres/peaks_dipy.nii.gz");
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  using dtf::io::FibreLayout;
  const dtf::ScalarVolume fa = dtf::computeFaMap(dtf::io::readTensorVolume(tensor.string()).field);
  const AxisTransform flipX = named({-1, 0, 0, 0, 1, 0, 0, 0, 1});
  struct Case {
    std::filesystem::path file;
    FibreLayout layout;
    bool right;
  };
  for (const Case& c :
       {Case{mrtrix, FibreLayout::MrtrixPeaks, true}, Case{dipy, FibreLayout::DipyPeaks, true},
        Case{dipy, FibreLayout::MrtrixPeaks, false}, Case{mrtrix, FibreLayout::DipyPeaks, false}}) {
    const auto loaded = dtf::io::readFibres(c.file.string(), c.layout);
    const glm::dmat3 toWorld = dtf::io::fibreFrameToWorld(loaded.set.grid, c.layout);
    for (const dtf::ScalarVolume* f : {static_cast<const dtf::ScalarVolume*>(nullptr), &fa}) {
      const auto r = checkFibreOrientation(loaded.set, toWorld, nullptr, f);
      const std::string what = c.file.filename().string() + " as " + dtf::io::fibreLayoutName(c.layout) +
                               (f ? " with FA" : " without FA") + ": " + r.reason;
      EXPECT_EQ(r.verdict, c.right ? Verdict::Ok : Verdict::Corrected) << what;
      EXPECT_EQ(r.correction, c.right ? AxisTransform{} : flipX) << what;
      // Measured: 8.8-10.5% without FA, 14.1-14.5% with it (the default threshold is 7%).
      EXPECT_GT(r.margin, f ? 0.12 : 0.08) << what;
      EXPECT_GT(r.whiteMatterVoxels, 5000u) << what;
      std::printf("%s: given %.4f best %.4f margin %.1f%% (%zu white-matter voxels)\n", what.c_str(),
                  r.scoreGiven, r.scoreBest, 100 * r.margin, r.whiteMatterVoxels);
    }
  }
}

} // namespace
