// SPDX-License-Identifier: GPL-3.0-or-later
// FSL bedpostx samples as cones: synthetic merged_th/ph/fNsamples files (4D, one volume per sample) with a
// known spread about a known direction, on an RAS grid (det > 0: FSL's frame negates x) and an LAS grid; the
// dyadic mean agrees with what the dyads reader makes of the same direction, and malformed folders fail
// naming the file.
#include "io/diffusion/uncertainty.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "support/test_env.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <gtest/gtest.h>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Unit vectors perpendicular to d.
void basis(glm::dvec3 d, glm::dvec3& u, glm::dvec3& v) {
  u = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  v = glm::cross(d, u);
}

// Writes a bedpostx folder with two populations on `grid`: population 1 samples on a ring at `spread1`
// degrees about fsl1 (FSL-frame direction), population 2 at `spread2` about fsl2 with fraction 0.2 in voxel 0
// only (0 elsewhere). Also dyads1/mean_f1samples with fsl1, for the dyads reader.
void writeFolder(const fs::path& dir, const Grid& grid, glm::dvec3 fsl1, double spread1, glm::dvec3 fsl2,
                 double spread2, int samples) {
  fs::create_directories(dir);
  const std::size_t n = grid.voxelCount();
  for (int pop = 1; pop <= 2; ++pop) {
    const glm::dvec3 d = glm::normalize(pop == 1 ? fsl1 : fsl2);
    const double spread = glm::radians(pop == 1 ? spread1 : spread2);
    glm::dvec3 u, v;
    basis(d, u, v);
    ScalarVolume th(grid, samples), ph(grid, samples), f(grid, samples);
    for (std::size_t vox = 0; vox < n; ++vox)
      for (int s = 0; s < samples; ++s) {
        const double a = 2 * kPi * s / samples;
        glm::dvec3 e = std::cos(spread) * d + std::sin(spread) * (std::cos(a) * u + std::sin(a) * v);
        if (s % 3 == 0) e = -e; // directions have no sign
        th.data[vox * samples + s] = static_cast<float>(std::acos(std::clamp(e.z, -1.0, 1.0)));
        ph.data[vox * samples + s] = static_cast<float>(std::atan2(e.y, e.x));
        f.data[vox * samples + s] = pop == 1 ? 0.5f : (vox == 0 ? 0.2f : 0.0f);
      }
    const std::string id = std::to_string(pop);
    io::writeScalarVolume((dir / ("merged_th" + id + "samples.nii.gz")).string(), th);
    io::writeScalarVolume((dir / ("merged_ph" + id + "samples.nii.gz")).string(), ph);
    io::writeScalarVolume((dir / ("merged_f" + id + "samples.nii.gz")).string(), f);
  }
  ScalarVolume dy(grid, 3), mf(grid, 1, 0.5f);
  const glm::dvec3 d1 = glm::normalize(fsl1);
  for (std::size_t vox = 0; vox < n; ++vox)
    for (int c = 0; c < 3; ++c)
      dy.data[vox * 3 + c] = static_cast<float>(d1[c]);
  io::writeScalarVolume((dir / "dyads1.nii.gz").string(), dy);
  io::writeScalarVolume((dir / "mean_f1samples.nii.gz").string(), mf);
}

} // namespace

TEST(BedpostxSamples, ConesAndFramesOnRasAndLasGrids) {
  const auto root = test::scratchDir();
  glm::dmat4 las(1.0);
  las[0][0] = -2.0; // x flipped: det < 0
  las[1][1] = las[2][2] = 2.0;
  for (bool isLas : {false, true}) {
    SCOPED_TRACE(isLas ? "LAS" : "RAS");
    const Grid grid = Grid::fromAffine({3, 2, 2}, isLas ? las : glm::dmat4(1.0));
    const fs::path dir = root / (isLas ? "las.bedpostX" : "ras.bedpostX");
    const glm::dvec3 fsl1(0.8, 0.5, 0.33), fsl2(0.1, 0.2, 1.0);
    writeFolder(dir, grid, fsl1, 12.0, fsl2, 25.0, 60);
    ASSERT_TRUE(io::isBedpostxSamplesPath(dir.string()));
    ASSERT_TRUE(io::isBedpostxSamplesPath((dir / "merged_ph2samples.nii.gz").string()));
    EXPECT_FALSE(io::isBedpostxSamplesPath((dir / "dyads1.nii.gz").string()));
    const io::BedpostxSamples b = io::readBedpostxSamples(dir.string());
    ASSERT_EQ(b.cone.size(), 2u);
    EXPECT_EQ(b.samples, 60);
    EXPECT_EQ(b.files.size(), 6u);
    // World direction written out by hand from FSL's rule: on RAS (det > 0) x is negated, on this LAS grid
    // (a pure x flip, det < 0) the voxel x axis already points left, so world x = -fsl x as well.
    const glm::dvec3 world1 = glm::normalize(glm::dvec3(-fsl1.x, fsl1.y, fsl1.z));
    const io::LoadedFibres dyads = io::readFibres(dir.string(), io::FibreLayout::Bedpostx);
    for (std::size_t v = 0; v < grid.voxelCount(); ++v) {
      EXPECT_NEAR(b.cone[0].data[v], 12.0, 0.01);
      const glm::dvec3 m(b.mean[0].data[v * 3], b.mean[0].data[v * 3 + 1], b.mean[0].data[v * 3 + 2]);
      EXPECT_GT(std::abs(glm::dot(m, world1)), 0.99999) << "voxel " << v;
      const glm::dvec3 dd(dyads.set.fibres[v * dyads.set.maxFibres].direction);
      EXPECT_GT(std::abs(glm::dot(m, dd)), 0.99999) << "samples and dyads disagree in voxel " << v;
      EXPECT_NEAR(b.meanFraction[0].data[v], 0.5, 1e-6);
      if (v == 0)
        EXPECT_NEAR(b.cone[1].data[v], 25.0, 0.01);
      else
        EXPECT_TRUE(std::isnan(b.cone[1].data[v])) << "population 2 is absent (f = 0) in voxel " << v;
    }
    // As a display map: population 1's cone.
    const ScalarVolume cone = io::readConeMap(dir.string());
    EXPECT_NEAR(cone.data[5], 12.0, 0.01);
  }
}

TEST(BedpostxSamples, MalformedFoldersAndConeMapsFailNamingTheFile) {
  const auto root = test::scratchDir();
  const fs::path dir = root / "broken.bedpostX";
  const Grid grid = Grid::fromAffine({2, 2, 2}, glm::dmat4(1.0));
  writeFolder(dir, grid, {1, 0, 0}, 5.0, {0, 1, 0}, 5.0, 10);
  auto expectError = [](const std::function<void()>& f, const std::string& file, const std::string& what) {
    try {
      f();
      ADD_FAILURE() << "no error for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  // Fewer samples in ph1 than th1.
  const std::string ph1 = (dir / "merged_ph1samples.nii.gz").string();
  io::writeScalarVolume(ph1, ScalarVolume(grid, 9));
  expectError([&] { io::readBedpostxSamples(dir.string()); }, ph1, "9 samples");
  fs::remove(ph1);
  expectError([&] { io::readBedpostxSamples(dir.string()); }, "merged_ph1samples", "no partner");
  expectError([&] { io::readBedpostxSamples((root / "nothing").string()); }, "nothing", "merged_th1samples");
  // A cone map with 4 volumes, or a value outside [0, 90].
  const std::string four = (root / "cone4d.nii").string();
  io::writeScalarVolume(four, ScalarVolume(grid, 4));
  expectError([&] { io::readConeMap(four); }, four, "4 volumes");
  ScalarVolume bad(grid, 1, 10.0f);
  bad.data[3] = 120.0f;
  const std::string badPath = (root / "cone_bad.nii").string();
  io::writeScalarVolume(badPath, bad);
  expectError([&] { io::readConeMap(badPath); }, badPath, "[0, 90]");
}
