// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info` on files that used to fool it: any file of a real FSL dtifit set describes the set's
// tensor (metrics, eigenvalues) like the tensor file; sign-normalised real peaks are fibre sets; data that
// fit a tensor and peaks alike, and a NRRD with a singular measurement frame, exit 2 naming the file.
#include "io/formats/tensor_io.h"
#include "io/model/tensor.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>
#include <regex>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

// The numbers after "key": (a number or an array of numbers), whatever the JSON spacing; empty when absent.
std::vector<double> jsonNumbers(const std::string& json, const std::string& key) {
  std::smatch m;
  std::vector<double> out;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\"\\s*:\\s*(\\[[^\\]]*\\]|-?[0-9.eE+-]+)")))
    return out;
  const std::string v = m[1];
  const std::regex num("-?[0-9][0-9.eE+-]*");
  for (auto it = std::sregex_iterator(v.begin(), v.end(), num); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod(it->str()));
  return out;
}

// Writes <dir>/dti_V1..V3 and L1..L3 from the world tensors of `field`, in FSL's frame (voxel axes, x
// negated when det(affine) > 0), as FSL dtifit does without --save_tensor.
void writeDtifitSet(const fs::path& dir, const TensorField& field) {
  glm::dmat3 rf = field.grid.rotation();
  if (glm::determinant(glm::dmat3(field.grid.voxelToWorld)) > 0) rf[0] = -rf[0];
  std::vector<ScalarVolume> v(3, ScalarVolume(field.grid, 3)), l(3, ScalarVolume(field.grid, 1));
  for (std::size_t i = 0; i < field.tensors.size(); ++i) {
    if (!field.valid[i]) continue;
    const EigenSystem e = eigenDecompose(field.tensors[i]);
    for (std::size_t n = 0; n < 3; ++n) {
      const glm::dvec3 f = glm::transpose(rf) * e.vectors[n];
      for (int c = 0; c < 3; ++c)
        v[n].data[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(f[c]);
      l[n].data[i] = static_cast<float>(e.values[static_cast<int>(n)]);
    }
  }
  for (std::size_t n = 0; n < 3; ++n) {
    io::writeScalarVolume((dir / ("dti_V" + std::to_string(n + 1) + ".nii.gz")).string(), v[n]);
    io::writeScalarVolume((dir / ("dti_L" + std::to_string(n + 1) + ".nii.gz")).string(), l[n]);
  }
}

} // namespace

TEST(DetectionCli, InfoOnADtifitMemberDescribesTheSetsTensor) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const fs::path dir = test::scratchDir();
  writeDtifitSet(dir, io::readTensorVolume(fsl.string()).field);
  // The corpus callosum voxel of the data's README: FA 0.8463, e1 left-right.
  const test::CliResult ref = test::runDtfabric("info '" + fsl.string() + "' --voxel 33,42,22 --json", dir);
  ASSERT_EQ(ref.exitCode, 0) << ref.err;
  for (const char* member : {"dti_V1.nii.gz", "dti_L2.nii.gz"}) {
    SCOPED_TRACE(member);
    const test::CliResult r =
        test::runDtfabric("info '" + (dir / member).string() + "' --voxel 33,42,22 --json", dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("\"is_tensor\""), std::string::npos) << r.out;
    const std::vector<double> fa = jsonNumbers(r.out, "fa"), faRef = jsonNumbers(ref.out, "fa");
    ASSERT_EQ(fa.size(), 1u) << r.out;
    EXPECT_NEAR(fa[0], 0.8463, 5e-4);
    EXPECT_NEAR(fa[0], faRef.at(0), 1e-5);
    const std::vector<double> ev = jsonNumbers(r.out, "eigenvalues"), evRef = jsonNumbers(ref.out, "eigenvalues");
    ASSERT_EQ(ev.size(), 3u) << r.out;
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_NEAR(ev[i], evRef.at(i), 1e-5 * evRef.at(0));
    EXPECT_NEAR(jsonNumbers(r.out, "md").at(0), 6.760e-4, 1e-6);
  }
  // The summary of the set: tensor facts, not the V1 volume's.
  const test::CliResult s = test::runDtfabric("info '" + (dir / "dti_V1.nii.gz").string() + "' --json", dir);
  ASSERT_EQ(s.exitCode, 0) << s.err;
  EXPECT_NE(s.out.find("FSL dtifit set"), std::string::npos) << s.out;
  EXPECT_GT(jsonNumbers(s.out, "valid_voxels").at(0), 40000);
}

TEST(DetectionCli, SignNormalisedPeaksAreDescribedAsFibresAndAmbiguousDataRefused) {
  DTF_SHARED_FILE(dipy, "iu_prisma_dwi/derived/fibres/peaks_dipy.nii.gz");
  const fs::path dir = test::scratchDir();
  const ScalarVolume peaks = io::readScalarVolume(dipy.string());
  for (int keep : {9, 6}) {
    ScalarVolume v(peaks.grid, keep);
    for (std::size_t i = 0; i < peaks.grid.voxelCount(); ++i)
      for (std::size_t c = 0; c < static_cast<std::size_t>(keep); ++c)
        v.data[i * static_cast<std::size_t>(keep) + c] = std::abs(peaks.data[i * 9 + c]);
    const fs::path p = dir / ("abs" + std::to_string(keep) + ".nii.gz");
    io::writeScalarVolume(p.string(), v);
    const test::CliResult r = test::runDtfabric("info '" + p.string() + "' --json", dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("\"is_fibres\""), std::string::npos) << r.out;
    EXPECT_EQ(jsonNumbers(r.out, "max_fibres").at(0), keep / 3) << r.out;
  }
  // One all-positive peak per voxel, the second triplet empty: also a diagonal tensor in MRtrix's order.
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = 2.0;
  ScalarVolume both(Grid::fromAffine({6, 5, 4}, a), 6, 0.0f);
  for (std::size_t i = 0; i < both.grid.voxelCount(); ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0 + double(i % 4), 0.3 + double(i % 3), 0.1 + double(i % 5)));
    for (int c = 0; c < 3; ++c)
      both.data[i * 6 + static_cast<std::size_t>(c)] = static_cast<float>(d[c]);
  }
  const fs::path p = dir / "both.nii.gz";
  io::writeScalarVolume(p.string(), both);
  const test::CliResult r = test::runDtfabric("info '" + p.string() + "'", dir);
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(p.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fits both"), std::string::npos) << r.err;
  EXPECT_EQ(test::runDtfabric("info '" + p.string() + "' --layout dipy-peaks", dir).exitCode, 0);
  EXPECT_EQ(test::runDtfabric("info '" + p.string() + "' --layout mrtrix", dir).exitCode, 0);
}

TEST(DetectionCli, NrrdWithASingularMeasurementFrameExitsTwo) {
  const fs::path dir = test::scratchDir();
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = 1.5;
  TensorField f = makeTensorField(Grid::fromAffine({4, 3, 2}, a));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    f.tensors[i] = SymTensor::fromMat(glm::dmat3(7e-4));
    f.valid[i] = 1;
  }
  const fs::path good = dir / "good.nrrd", bad = dir / "singular frame.nrrd";
  io::writeTensorVolume(good.string(), f, io::TensorLayout::Auto);
  std::ifstream in(good, std::ios::binary);
  std::string text(std::istreambuf_iterator<char>(in), {});
  const auto at = text.find("measurement frame: ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find('\n', at) - at, "measurement frame: (1,0,0) (0,1,0) (0,0,0)");
  std::ofstream(bad, std::ios::binary) << text;
  ASSERT_EQ(test::runDtfabric("info '" + good.string() + "'", dir).exitCode, 0);
  const test::CliResult r = test::runDtfabric("info '" + bad.string() + "'", dir);
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("singular"), std::string::npos) << r.err;
}
