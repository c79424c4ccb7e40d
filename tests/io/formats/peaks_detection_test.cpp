// SPDX-License-Identifier: GPL-3.0-or-later
// Tensor or fibre peaks, decided by what the values can be: real MRtrix and DIPY peaks whose vectors were
// sign-normalised (the case that counting negative values got wrong), as 9 volumes and cut to 6 (two
// peaks), are fibre sets; real tensors in every layout are still tensors; a file that fits both is refused
// until a layout is named.
#include "io/formats/fibre_io.h"
#include "io/formats/format_detail.h"
#include "io/formats/tensor_io.h"
#include "io/input.h"
#include "io/model/error.h"
#include "support/test_env.h"

#include <gtest/gtest.h>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

enum class Norm { None, XPositive, ZPositive, AllPositive };

// The peaks file's triplets with signs normalised as a tool might (x >= 0, z >= 0, or every component >= 0),
// keeping the first `keep` volumes.
ScalarVolume normalised(const ScalarVolume& in, Norm n, int keep) {
  ScalarVolume out(in.grid, keep);
  const auto c = static_cast<std::size_t>(in.components), kc = static_cast<std::size_t>(keep);
  for (std::size_t v = 0; v < in.grid.voxelCount(); ++v)
    for (std::size_t t = 0; t + 2 < kc; t += 3) {
      float x[3] = {in.data[v * c + t], in.data[v * c + t + 1], in.data[v * c + t + 2]};
      const float s = n == Norm::XPositive ? (x[0] < 0 ? -1.0f : 1.0f) : n == Norm::ZPositive ? (x[2] < 0 ? -1.0f : 1.0f) : 1.0f;
      for (std::size_t i = 0; i < 3; ++i)
        out.data[v * kc + t + i] = n == Norm::AllPositive ? std::abs(x[i]) : s * x[i];
    }
  return out;
}

const char* normName(Norm n) {
  return n == Norm::None ? "none" : n == Norm::XPositive ? "x" : n == Norm::ZPositive ? "z" : "abs";
}

std::string refusal(const std::string& p) {
  try {
    io::readTensorVolume(p);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

} // namespace

TEST(PeaksDetection, SignNormalisedRealPeaksAreFibreSetsWithNineOrSixVolumes) {
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/fibres/peaks_mrtrix.nii.gz");
  DTF_SHARED_FILE(dipy, "iu_prisma_dwi/derived/fibres/peaks_dipy.nii.gz");
  const fs::path dir = test::scratchDir();
  for (const auto& [tool, src] : {std::pair{"mrtrix", mrtrix}, std::pair{"dipy", dipy}}) {
    const ScalarVolume peaks = io::readScalarVolume(src.string());
    ASSERT_EQ(peaks.components, 9);
    for (Norm n : {Norm::None, Norm::XPositive, Norm::ZPositive, Norm::AllPositive})
      for (int keep : {9, 6}) {
        const std::string name = std::string(tool) + "_" + normName(n) + "_" + std::to_string(keep) + ".nii.gz";
        SCOPED_TRACE(name);
        const std::string p = (dir / name).string();
        io::writeScalarVolume(p, normalised(peaks, n, keep));
        std::string why;
        EXPECT_TRUE(io::looksLikeFibres(p, &why)) << why;
        // What render and view open: a fibre set, read with as many populations as triplets.
        io::InputRequest r;
        r.path = p;
        const io::OpenedInput in = io::openInput(r);
        ASSERT_EQ(in.kind, io::InputKind::Fibres) << in.reason;
        EXPECT_EQ(io::readInputFibres(in).set.maxFibres, keep / 3);
        if (keep == 6) {
          // The tensor reader refuses it, saying it holds peaks.
          const std::string msg = refusal(p);
          EXPECT_EQ(msg.rfind(p, 0), 0u) << msg;
          EXPECT_NE(msg.find("fibre peaks"), std::string::npos) << msg;
        }
      }
  }
}

TEST(PeaksDetection, RealTensorsInEveryLayoutAreStillTensors) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(mrtrix, "iu_prisma_dwi/derived/dti_tensor_mrtrix.nii.gz");
  DTF_SHARED_FILE(sym, "iu_prisma_dwi/derived/dti_tensor_symmatrix5d.nii.gz");
  DTF_SHARED_FILE(mif, "iu_prisma_dwi/derived/dti_tensor.mif.gz");
  const std::pair<fs::path, io::TensorLayout> cases[] = {{fsl, io::TensorLayout::Fsl},
                                                          {mrtrix, io::TensorLayout::Mrtrix},
                                                          {sym, io::TensorLayout::Symmatrix},
                                                          {mif, io::TensorLayout::Mrtrix}};
  for (const auto& [p, layout] : cases) {
    SCOPED_TRACE(p.string());
    std::string why;
    EXPECT_FALSE(io::looksLikeFibres(p.string(), &why)) << why;
    io::InputRequest r;
    r.path = p.string();
    EXPECT_EQ(io::openInput(r).kind, io::InputKind::Tensors);
    const io::LoadedTensors t = io::readTensorVolume(p.string());
    EXPECT_EQ(t.layout, layout) << t.layoutReason;
    EXPECT_GT(t.field.tensors.size(), 0u);
  }
  // The evidence itself: nearly every voxel positive semi-definite in the file's own order only.
  const io::detail::ComponentEvidence e = io::detail::componentEvidence(io::readScalarVolume(fsl.string()));
  EXPECT_EQ(e.kind, io::detail::ComponentKind::Tensor) << e.evidence;
  EXPECT_GT(e.psdFsl, 0.99) << e.evidence;
  EXPECT_LT(e.psdMrtrix, 0.05) << e.evidence;
}

TEST(PeaksDetection, DataThatFitBothAreRefusedUntilALayoutIsNamed) {
  // One peak per voxel with every component positive and the second triplet empty (zeros): as MRtrix's
  // tensor order (xx yy zz xy xz yz) that is a diagonal positive tensor in every voxel.
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = 2.0;
  ScalarVolume v(Grid::fromAffine({8, 6, 5}, a), 6, 0.0f);
  for (std::size_t i = 0; i < v.grid.voxelCount(); ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0 + double(i % 5), 0.5 + double(i % 3), 0.2 + double(i % 7)));
    for (int c = 0; c < 3; ++c)
      v.data[i * 6 + static_cast<std::size_t>(c)] = static_cast<float>(d[c]);
  }
  const fs::path dir = test::scratchDir();
  const std::string p = (dir / "both.nii.gz").string();
  io::writeScalarVolume(p, v);
  const std::string msg = refusal(p);
  EXPECT_EQ(msg.rfind(p, 0), 0u) << msg;
  EXPECT_NE(msg.find("fits both"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--layout"), std::string::npos) << msg;
  std::string why;
  EXPECT_FALSE(io::looksLikeFibres(p, &why));
  EXPECT_NE(why.find("fits both"), std::string::npos) << why;
  // Named, either reading goes through.
  EXPECT_EQ(io::readTensorVolume(p, io::TensorLayout::Mrtrix).field.tensors.size(), v.grid.voxelCount());
  EXPECT_EQ(io::readFibres(p, io::FibreLayout::DipyPeaks).set.occupiedVoxels(), v.grid.voxelCount());
}
