// SPDX-License-Identifier: GPL-3.0-or-later
// Other tools' formats through the real executable: `info` names the format and why, `fit` takes an MRtrix
// DWI with its dw_scheme and a DSI Studio SRC without bval/bvec files, and writes .mif and .nrrd outputs
// that read back as the same world tensors as a NIfTI fit.
#include "io/diffusion/dwi.h"
#include "io/formats/format_detail.h"
#include "io/formats/tensor_io.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>

namespace fs = std::filesystem;
using namespace dtf;
using dtf::test::CliResult;
using dtf::test::runDtfabric;

namespace {

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// Largest component difference, relative to the voxel's largest component, over voxels valid in both
// fields at the same world position; `compared` counts them.
double maxRelativeDifference(const TensorField& a, const TensorField& b, std::size_t& compared) {
  double worst = 0;
  compared = 0;
  for (int k = 0; k < a.grid.dims.z; ++k)
    for (int j = 0; j < a.grid.dims.y; ++j)
      for (int i = 0; i < a.grid.dims.x; ++i) {
        const glm::dvec3 v = b.grid.toVoxel(a.grid.toWorld(glm::dvec3(i, j, k)));
        const glm::ivec3 r(std::lround(v.x), std::lround(v.y), std::lround(v.z));
        if (!b.grid.contains(r.x, r.y, r.z)) continue;
        const std::size_t ia = a.grid.index(i, j, k), ib = b.grid.index(r.x, r.y, r.z);
        if (!a.valid[ia] || !b.valid[ib]) continue;
        ++compared;
        const auto ca = a.tensors[ia].components(), cb = b.tensors[ib].components();
        double scale = 1e-30, d = 0;
        for (int c = 0; c < 6; ++c) {
          scale = std::max(scale, std::abs(double(ca[c])));
          d = std::max(d, std::abs(double(ca[c]) - double(cb[c])));
        }
        worst = std::max(worst, d / scale);
      }
  return worst;
}

} // namespace

TEST(FormatsCli, InfoNamesTheFormatAndWhy) {
  DTF_SHARED_FILE(mif, "iu_prisma_dwi/derived/dti_tensor.mif.gz");
  DTF_SHARED_FILE(src, "niivue_other_tools/dsistudio.src.gz");
  DTF_SHARED_FILE(mask, "niivue_other_tools/mask_1bit.mif");
  const fs::path dir = test::scratchDir();
  CliResult r = runDtfabric("info " + q(mif), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("format:       MRtrix image, datatype Float32LE"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("format why:   content starts with 'mrtrix image'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("MRtrix image; "), std::string::npos) << "layout reason:\n" << r.out;
  EXPECT_NE(r.out.find("orientation:  RAS"), std::string::npos) << r.out;
  r = runDtfabric("info --json " + q(src), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("\"file_format\": \"DSI Studio SRC\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"dims\": [72, 72, 36, 21]"), std::string::npos) << r.out;
  r = runDtfabric("info " + q(mask), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("datatype Bit"), std::string::npos) << r.out;
}

TEST(FormatsCli, FitTakesAnMrtrixDwiWithItsDwSchemeAndWritesMif) {
  DTF_SHARED_FILE(dwiNii, "iu_prisma_dwi/dwi.nii.gz");
  const fs::path dir = test::scratchDir();
  const fs::path bval = dwiNii.parent_path() / "dwi.bval", bvec = dwiNii.parent_path() / "dwi.bvec";
  const io::Dwi dwi = io::readDwi(dwiNii.string(), bval.string(), bvec.string());
  // As mrconvert stores it: an RAS transform (i flipped, so the same world positions), world gradients in
  // dw_scheme, the bytes in the NIfTI's order (layout -0).
  const Grid& g = dwi.signal.grid;
  ScalarVolume flipped(g, dwi.signal.components);
  flipped.grid.voxelToWorld[0] = -g.voxelToWorld[0];
  flipped.grid.voxelToWorld[3] = g.voxelToWorld * glm::dvec4(g.dims.x - 1, 0, 0, 1);
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i)
        for (int c = 0; c < flipped.components; ++c)
          flipped.at(i, j, k, c) = dwi.signal.at(g.dims.x - 1 - i, j, k, c);
  std::vector<std::string> scheme;
  for (std::size_t v = 0; v < dwi.bvals.size(); ++v) {
    const glm::dvec3 w = dwi.gradientsWorld[v];
    char line[160];
    std::snprintf(line, sizeof line, "dw_scheme: %.9g,%.9g,%.9g,%.9g", w.x, w.y, w.z, dwi.bvals[v]);
    scheme.emplace_back(line);
  }
  io::detail::writeMrtrix((dir / "dwi.mif").string(), flipped, {-1, 2, 3, 4}, scheme);

  CliResult a = runDtfabric("fit " + q(dir / "dwi.mif") + " -o " + q(dir / "a.mif.gz"), dir);
  ASSERT_EQ(a.exitCode, 0) << a.err;
  CliResult b = runDtfabric("fit " + q(dwiNii) + " -o " + q(dir / "b.nii.gz"), dir);
  ASSERT_EQ(b.exitCode, 0) << b.err;
  CliResult n = runDtfabric("fit " + q(dwiNii) + " -o " + q(dir / "c.nrrd"), dir);
  ASSERT_EQ(n.exitCode, 0) << n.err;
  const TensorField fa = io::readTensorVolume((dir / "a.mif.gz").string()).field;
  const TensorField fb = io::readTensorVolume((dir / "b.nii.gz").string()).field;
  const TensorField fc = io::readTensorVolume((dir / "c.nrrd").string()).field;
  EXPECT_EQ(fa.grid.orientationCode(), "RAS");
  EXPECT_EQ(fb.grid.orientationCode(), "LAS");
  std::size_t compared = 0;
  // Same signals, same world gradients: the fits agree up to float rounding of the gradients in dw_scheme.
  EXPECT_LT(maxRelativeDifference(fb, fa, compared), 1e-3);
  EXPECT_GT(compared, 40000u);
  EXPECT_LT(maxRelativeDifference(fb, fc, compared), 1e-6);
  EXPECT_GT(compared, 40000u);
}

TEST(FormatsCli, FitTakesADsiStudioSrcWithoutGradientFiles) {
  DTF_SHARED_FILE(src, "niivue_other_tools/dsistudio.src.gz");
  const fs::path dir = test::scratchDir();
  CliResult r = runDtfabric("fit " + q(src) + " -o " + q(dir / "src_fit.nii.gz"), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const io::LoadedTensors t = io::readTensorVolume((dir / "src_fit.nii.gz").string());
  EXPECT_EQ(t.field.grid.dims, glm::ivec3(72, 72, 36));
  EXPECT_EQ(t.field.grid.orientationCode(), "LPS");
  EXPECT_GT(std::count(t.field.valid.begin(), t.field.valid.end(), 1), 30000);
}
