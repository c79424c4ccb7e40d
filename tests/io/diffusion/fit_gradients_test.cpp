// SPDX-License-Identifier: GPL-3.0-or-later
// bval/bvec parsing and the gradient table checks of makeDwi: layouts, NaN rows, counts, bad text,
// zero vectors, normalisation and the rotation of bvec-frame directions into world RAS.
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "support/test_env.h"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>

using namespace dtf;
using namespace dtf::io;

namespace {

std::string writeText(const std::string& name, const std::string& text) {
  auto p = dtf::test::scratchDir() / name;
  std::ofstream(p) << text;
  return p.string();
}

// Runs `f`, expects an InputError whose message contains every string in `parts`.
template <typename F> void expectInputError(F f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

Volume<float> signal(int volumes, const glm::dmat4& affine = glm::dmat4(1.0)) {
  return Volume<float>(Grid::fromAffine({2, 2, 2}, affine), volumes, 100.0f);
}

} // namespace

TEST(Bvals, WhitespaceSeparatedOnSeveralLines) {
  auto p = writeText("a.bval", "0 1000\t1000\n\n  2000 \r\n3000\n");
  EXPECT_EQ(readBvals(p), (std::vector<double>{0, 1000, 1000, 2000, 3000}));
}

TEST(Bvals, NonNumericNegativeEmptyAndMissingAreErrors) {
  expectInputError([] { readBvals(writeText("x.bval", "0 1000\n1000 abc 1000\n")); },
                   {"x.bval", "line 2", "abc"});
  expectInputError([] { readBvals(writeText("n.bval", "0 -1000\n")); }, {"n.bval", "line 1"});
  expectInputError([] { readBvals(writeText("e.bval", "\n \n")); }, {"e.bval", "no numbers"});
  expectInputError([] { readBvals("/nonexistent/dir/missing.bval"); }, {"missing.bval"});
}

TEST(Bvecs, FslThreeByNAndNByThreeGiveTheSameDirections) {
  auto fsl = readBvecs(writeText("fsl.bvec", "0 1 0 0.6\n0 0 1 0.8\n0 0 0 0\n"));
  auto rows = readBvecs(writeText("rows.bvec", "0 0 0\n1 0 0\n0 1 0\n0.6 0.8 0\n"));
  ASSERT_EQ(fsl.size(), 4u);
  ASSERT_EQ(rows.size(), 4u);
  for (int n = 0; n < 4; ++n)
    EXPECT_EQ(fsl[n], rows[n]) << n;
  EXPECT_EQ(fsl[3], glm::dvec3(0.6, 0.8, 0));
}

TEST(Bvecs, NanRowsAreKeptAndThreeByThreeReadsAsFsl) {
  auto v = readBvecs(writeText("nan.bvec", "nan nan nan\n1 0 0\n0 1 0\n0 0 1\n"));
  ASSERT_EQ(v.size(), 4u);
  EXPECT_TRUE(std::isnan(v[0].x) && std::isnan(v[0].y) && std::isnan(v[0].z));
  auto t = readBvecs(writeText("t.bvec", "1 2 3\n4 5 6\n7 8 9\n"));
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0], glm::dvec3(1, 4, 7)); // columns are directions in FSL's layout
}

TEST(Bvecs, BadShapeNonNumericAndCountMismatchNameTheFile) {
  expectInputError([] { readBvecs(writeText("shape.bvec", "1 0\n0 1\n")); }, {"shape.bvec", "3 rows"});
  expectInputError([] { readBvecs(writeText("ragged.bvec", "1 0 0 1\n0 1 0\n0 0 1 0\n")); }, {"ragged.bvec"});
  expectInputError([] { readBvecs(writeText("text.bvec", "1 0 0\n0 1 0\n0 0 x1\n")); },
                   {"text.bvec", "line 3", "x1"});
  expectInputError([] { readBvecs(writeText("count.bvec", "1 0 0\n0 1 0\n0 0 1\n1 1 0\n"), 5); },
                   {"count.bvec", "4 directions", "5"});
}

TEST(Bvecs, RealDipyFilesInBothLayouts) {
  DTF_SHARED_FILE(nx3, "dipy_small/small_64D.bvec");
  DTF_SHARED_FILE(fsl, "dipy_small/small_101D.bvec");
  auto a = readBvecs(nx3.string());
  ASSERT_EQ(a.size(), 65u);
  EXPECT_TRUE(std::isnan(a[0].x));
  EXPECT_NEAR(glm::length(a[1]), 1.0, 1e-6);
  EXPECT_NEAR(a[1].y, 0.9999827, 1e-6);
  auto b = readBvecs(fsl.string());
  ASSERT_EQ(b.size(), 102u);
  EXPECT_NEAR(b[0].x, 0.51103121042251, 1e-12);
}

TEST(MakeDwi, CountMismatchNamesBothFilesAndCounts) {
  std::vector<glm::dvec3> g(4, glm::dvec3(1, 0, 0));
  expectInputError(
      [&] {
        makeDwi(signal(4), {0, 1000, 1000}, g, 50, "dwi.nii.gz", "dwi.bval", "dwi.bvec");
      },
      {"dwi.bval", "3 b-values", "dwi.nii.gz", "4 volumes"});
  expectInputError(
      [&] {
        makeDwi(signal(5), {0, 1000, 1000, 1000, 1000}, g, 50, "dwi.nii.gz", "dwi.bval", "dwi.bvec");
      },
      {"dwi.bvec", "4 directions", "dwi.nii.gz", "5 volumes"});
}

TEST(MakeDwi, ZeroOrNanDirectionOnlyAtBZero) {
  const double nan = std::nan("");
  std::vector<glm::dvec3> g{glm::dvec3(0), glm::dvec3(nan), {0, 1, 0}, {0, 0, 1}};
  Dwi ok = makeDwi(signal(4), {0, 40, 1000, 1000}, g, 50);
  EXPECT_EQ(ok.gradientsWorld[0], glm::dvec3(0));
  EXPECT_EQ(ok.gradientsWorld[1], glm::dvec3(0)); // NaN row at b=40 <= threshold: no direction
  expectInputError(
      [&] {
        makeDwi(signal(4), {0, 1000, 1000, 1000}, g, 50, "d", "b", "dwi.bvec");
      },
      {"dwi.bvec", "volume 1", "NaN"});
  expectInputError(
      [&] {
        makeDwi(signal(4), {1000, 0, 1000, 1000}, g, 50, "d", "b", "dwi.bvec");
      },
      {"dwi.bvec", "volume 0", "zero"});
}

TEST(MakeDwi, NonUnitDirectionsAreNormalisedWithAWarning) {
  std::vector<std::string> warnings;
  setLogSink([&](LogLevel l, const std::string& m) {
    if (l == LogLevel::Warning) warnings.push_back(m);
  });
  Dwi slightly = makeDwi(signal(2), {1000, 1000}, {{0, 0, 1.02}, {0, 1, 0}}, 50);
  EXPECT_TRUE(warnings.empty()) << "2% off unit is rounding in bvec files, not worth a warning";
  Dwi far = makeDwi(signal(2), {1000, 1000}, {{0, 0, 2.0}, {0, 1, 0}}, 50, "d", "b", "far.bvec");
  setLogSink({});
  EXPECT_NEAR(glm::length(slightly.gradientsWorld[0]), 1.0, 1e-12);
  EXPECT_EQ(far.gradientsWorld[0], glm::dvec3(0, 0, 1));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("far.bvec"), std::string::npos);
}

TEST(MakeDwi, DirectionsRotateFromBvecFrameToWorld) {
  // LAS (det < 0): bvec = voxel axes, voxel i = world -x.
  glm::dmat4 las(1.0);
  las[0][0] = -3;
  las[1][1] = 3;
  las[2][2] = 3;
  // RAS (det > 0): FSL negates x, voxel i = world +x: again world -x.
  glm::dmat4 ras(1.0);
  ras[0][0] = 2;
  // LPS-like with det > 0 (i = world -x, j = world -y): bvec x negated then rotated: (+x, -y, z).
  glm::dmat4 lps(1.0);
  lps[0][0] = -1;
  lps[1][1] = -1;
  // Axial rotated 90 degrees about z, det > 0: i -> world +y, j -> world -x.
  glm::dmat4 rot(0.0);
  rot[0] = glm::dvec4(0, 2, 0, 0);
  rot[1] = glm::dvec4(-2, 0, 0, 0);
  rot[2] = glm::dvec4(0, 0, 2, 0);
  rot[3] = glm::dvec4(0, 0, 0, 1);
  const std::vector<glm::dvec3> g{{0.6, 0.8, 0}, {0, 0.6, 0.8}};
  struct Case {
    glm::dmat4 affine;
    glm::dvec3 first, second;
  };
  const Case cases[] = {{las, {-0.6, 0.8, 0}, {0, 0.6, 0.8}},
                        {ras, {-0.6, 0.8, 0}, {0, 0.6, 0.8}},
                        {lps, {0.6, -0.8, 0}, {0, -0.6, 0.8}},
                        // bvec (0.6, 0.8, 0) -> flipped (-0.6, 0.8, 0) -> world (-0.8, -0.6, 0)
                        {rot, {-0.8, -0.6, 0}, {-0.6, 0, 0.8}}};
  for (const auto& c : cases) {
    Dwi d = makeDwi(signal(2, c.affine), {1000, 1000}, g, 50);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(d.gradientsWorld[0][a], c.first[a], 1e-12) << "axis " << a;
      EXPECT_NEAR(d.gradientsWorld[1][a], c.second[a], 1e-12) << "axis " << a;
    }
  }
}
