// SPDX-License-Identifier: GPL-3.0-or-later
// Other tools' formats read into the canonical TensorField: MRtrix images (the real MRtrix-written tensor,
// hand-built files of known layout, files written with several stride layouts, the niivue oblique / uint8 /
// 1-bit images), FSL dtifit eigen-systems, NRRD tensors in RAS and LPS with measurement frames and axis
// orders, DSI Studio SRC/FIB. The reference everywhere is the same world tensor at the same world position.
#include "io/formats/dsi_studio.h"
#include "io/diffusion/dwi.h"
#include "io/formats/fibre_io.h"
#include "io/formats/format_detail.h"
#include "io/formats/formats.h"
#include "io/model/error.h"
#include "io/model/tensor.h"
#include "io/formats/tensor_io.h"
#include "support/test_env.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <gtest/gtest.h>
#include <zlib.h>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string gzipBytes(const std::string& raw) {
  uLongf n = compressBound(static_cast<uLong>(raw.size())) + 64;
  std::string out(n, '\0');
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = static_cast<uInt>(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

template <typename T> void put(std::string& s, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

double maxAbs(const SymTensor& a, const SymTensor& b) {
  auto ca = a.components(), cb = b.components();
  double m = 0;
  for (int k = 0; k < 6; ++k)
    m = std::max(m, std::abs(double(ca[k]) - double(cb[k])));
  return m;
}

// Compares two fields voxel by voxel at the same world position (grids may differ in axis order or
// direction). Returns the largest component difference; counts voxels compared and validity mismatches.
struct WorldCompare {
  double maxDiff = 0;    // mm^2/s
  double maxRelDiff = 0; // relative to the voxel's largest reference component (float32 storage: ~1e-7)
  std::size_t compared = 0, validityMismatch = 0, offGrid = 0;
};
WorldCompare compareInWorld(const TensorField& ref, const TensorField& other) {
  WorldCompare c;
  for (int k = 0; k < ref.grid.dims.z; ++k)
    for (int j = 0; j < ref.grid.dims.y; ++j)
      for (int i = 0; i < ref.grid.dims.x; ++i) {
        const glm::dvec3 v = other.grid.toVoxel(ref.grid.toWorld(glm::dvec3(i, j, k)));
        const glm::ivec3 r(std::lround(v.x), std::lround(v.y), std::lround(v.z));
        if (glm::length(v - glm::dvec3(r)) > 1e-3 || !other.grid.contains(r.x, r.y, r.z)) {
          ++c.offGrid;
          continue;
        }
        const std::size_t a = ref.grid.index(i, j, k), b = other.grid.index(r.x, r.y, r.z);
        if (ref.valid[a] != other.valid[b]) ++c.validityMismatch;
        if (!ref.valid[a]) continue;
        ++c.compared;
        const double d = maxAbs(ref.tensors[a], other.tensors[b]);
        double scale = 0;
        for (float x : ref.tensors[a].components())
          scale = std::max(scale, std::abs(double(x)));
        c.maxDiff = std::max(c.maxDiff, d);
        c.maxRelDiff = std::max(c.maxRelDiff, d / std::max(scale, 1e-30));
      }
  return c;
}

io::LoadedTensors realFslTensor() {
  return io::readTensorVolume((test::sharedDataDir() / "iu_prisma_dwi/derived/dti_tensor.nii.gz").string());
}

} // namespace

// ---------------------------------------------------------------- MRtrix

TEST(MrtrixImage, RealMrtrixTensorEqualsItsNiftiAtEveryWorldPosition) {
  DTF_SHARED_FILE(mif, "iu_prisma_dwi/derived/dti_tensor.mif.gz");
  DTF_SHARED_FILE(nii, "iu_prisma_dwi/derived/dti_tensor_mrtrix.nii.gz");
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  EXPECT_EQ(io::detectFormat(mif.string()).format, io::FileFormat::Mrtrix);
  const io::LoadedTensors m = io::readTensorVolume(mif.string());
  const io::LoadedTensors n = io::readTensorVolume(nii.string(), io::TensorLayout::Mrtrix);
  EXPECT_EQ(m.layout, io::TensorLayout::Mrtrix) << m.layoutReason;
  EXPECT_EQ(m.header.format, "MRtrix image");
  // mrconvert stored the LAS NIfTI with an RAS transform and layout -0,+1,+2,+3: same voxels, i reversed.
  EXPECT_EQ(m.field.grid.orientationCode(), "RAS");
  EXPECT_EQ(n.field.grid.orientationCode(), "LAS");
  EXPECT_EQ(m.field.grid.dims, n.field.grid.dims);
  EXPECT_NEAR(m.field.grid.toWorld(glm::dvec3(71, 0, 0)).x, n.field.grid.toWorld(glm::dvec3(0, 0, 0)).x,
              1e-4);
  const WorldCompare c = compareInWorld(n.field, m.field);
  EXPECT_EQ(c.offGrid, 0u);
  EXPECT_EQ(c.validityMismatch, 0u);
  EXPECT_GT(c.compared, 40000u);
  EXPECT_EQ(c.maxDiff, 0.0) << "the same float32 values, so exactly equal";
  EXPECT_EQ(m.nanVoxels, 1u); // the NaN voxel where b0 = 0

  // Against DIPY's independent fit in FSL layout (voxel frame): close in world space only after rotation.
  const io::LoadedTensors f = io::readTensorVolume(fsl.string());
  std::vector<double> diff;
  double sameSign = 0, flipped = 0;
  for (std::size_t i = 0; i < f.field.tensors.size(); ++i) {
    if (!f.field.valid[i]) continue;
    const glm::ivec3 ijk(static_cast<int>(i % 72), static_cast<int>(i / 72 % 72), static_cast<int>(i / 5184));
    const std::size_t mi = m.field.grid.index(71 - ijk.x, ijk.y, ijk.z);
    if (!m.field.valid[mi]) continue;
    const auto a = f.field.tensors[i].components(), b = m.field.tensors[mi].components();
    for (int k = 0; k < 6; ++k)
      diff.push_back(std::abs(a[k] - b[k]));
    sameSign += a[1] * b[1];
    flipped += -a[1] * b[1];
  }
  ASSERT_GT(diff.size(), 100000u);
  std::nth_element(diff.begin(), diff.begin() + static_cast<std::ptrdiff_t>(diff.size() / 2), diff.end());
  EXPECT_LT(diff[diff.size() / 2], 2e-6) << "median |D_mrtrix - D_dipy| in world space (mm^2/s)";
  EXPECT_GT(sameSign, 0) << "xy components agree in sign in world space";
  EXPECT_LT(flipped, 0);
}

TEST(MrtrixImage, HandBuiltLayoutIsReadAsMrtrixDefinesIt) {
  // 3x2x2 voxels x 2 volumes, layout +1,-2,+3,+0: the volume axis fastest, then i, then j stored in
  // reverse, then k; Int16BE with scaling 0.5,2 (value = 0.5 + 2 * stored).
  const fs::path dir = test::scratchDir();
  std::string data;
  for (int k = 0; k < 2; ++k)
    for (int jd = 0; jd < 2; ++jd)
      for (int i = 0; i < 3; ++i)
        for (int v = 0; v < 2; ++v) {
          const int j = 1 - jd;
          put<std::int16_t>(data, static_cast<std::int16_t>(1000 * v + 100 * i + 10 * j + k), true);
        }
  std::string head = "mrtrix image\ndim: 3,2,2,2\nvox: 2,3,4,nan\nlayout: +1,-2,+3,+0\ndatatype: Int16BE\n"
                     "transform: 0,-1,0,10\ntransform: 1,0,0,20\ntransform: 0,0,1,30\nscaling: 0.5,2\n";
  head += "file: . 256\nEND\n";
  head.resize(256, '\0');
  writeBytes(dir / "hand.mif", head + data);
  ScalarVolume v = io::readScalarVolume((dir / "hand.mif").string());
  ASSERT_EQ(v.components, 2);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 2; ++c)
          EXPECT_EQ(v.at(i, j, k, c), 0.5f + 2.0f * static_cast<float>(1000 * c + 100 * i + 10 * j + k))
              << i << "," << j << "," << k << "," << c;
  // voxel -> world = [R * diag(vox) | t]: i runs along +y (2 mm), j along -x (3 mm).
  const glm::dvec3 w = v.grid.toWorld(glm::dvec3(1, 1, 1));
  EXPECT_NEAR(w.x, 10 - 3, 1e-12);
  EXPECT_NEAR(w.y, 20 + 2, 1e-12);
  EXPECT_NEAR(w.z, 30 + 4, 1e-12);
  EXPECT_EQ(v.grid.spacing, glm::dvec3(2, 3, 4));

  // The same through a .mih header and a separate data file at an offset.
  std::string mih = "mrtrix image\ndim: 3,2,2,2\nvox: 2,3,4,nan\nlayout: +1,-2,+3,+0\ndatatype: Int16BE\n"
                    "transform: 0,-1,0,10\ntransform: 1,0,0,20\ntransform: 0,0,1,30\nscaling: 0.5,2\n"
                    "file: hand.dat 7\nEND\n";
  writeBytes(dir / "hand.mih", mih);
  writeBytes(dir / "hand.dat", "1234567" + data);
  ScalarVolume h = io::readScalarVolume((dir / "hand.mih").string());
  EXPECT_EQ(h.data, v.data);
}

TEST(MrtrixImage, StrideLayoutsRoundTripTheRealTensor) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const fs::path dir = test::scratchDir();
  const io::LoadedTensors ref = realFslTensor();
  // Written through the MRtrix convention (xx yy zz xy xz yz, world frame).
  ScalarVolume mr(ref.field.grid, 6);
  for (std::size_t i = 0; i < ref.field.tensors.size(); ++i) {
    if (!ref.field.valid[i]) continue;
    const glm::dmat3 m = ref.field.tensors[i].toMat();
    const double c[6] = {m[0][0], m[1][1], m[2][2], m[0][1], m[0][2], m[1][2]};
    for (int k = 0; k < 6; ++k)
      mr.data[i * 6 + static_cast<std::size_t>(k)] = static_cast<float>(c[k]);
  }
  const std::vector<std::pair<std::string, std::vector<int>>> layouts = {{"plain.mif", {1, 2, 3, 4}},
                                                                         {"flipx.mif", {-1, 2, 3, 4}},
                                                                         {"volfirst.mif.gz", {4, 1, 2, 3}},
                                                                         {"mixed.mif", {-3, 1, -4, 2}},
                                                                         {"flipall.mih", {-1, -2, -3, -4}}};
  for (const auto& [name, strides] : layouts) {
    SCOPED_TRACE(name);
    io::detail::writeMrtrix((dir / name).string(), mr, strides);
    const io::LoadedTensors back = io::readTensorVolume((dir / name).string());
    EXPECT_EQ(back.layout, io::TensorLayout::Mrtrix) << back.layoutReason;
    const WorldCompare c = compareInWorld(ref.field, back.field);
    EXPECT_EQ(c.offGrid, 0u);
    EXPECT_EQ(c.validityMismatch, 0u);
    EXPECT_LT(c.maxDiff, 1e-9);
  }
  // The file a stride layout writes really differs on disk (a layout that is ignored would not).
  const auto a = io::detail::readFileBytes((dir / "plain.mif").string());
  const auto b = io::detail::readFileBytes((dir / "flipx.mif").string());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_NE(a, b);
  // And the tensor writer's own .mif output reads back too.
  io::writeTensorVolume((dir / "fit.mif.gz").string(), ref.field, io::TensorLayout::Fsl);
  EXPECT_LT(compareInWorld(ref.field, io::readTensorVolume((dir / "fit.mif.gz").string()).field).maxDiff,
            1e-9);
}

TEST(MrtrixImage, NiivueFilesLoadWithTheirGeometry) {
  DTF_SHARED_FILE(tmpl, "niivue_other_tools/template.mif.gz");
  DTF_SHARED_FILE(ras, "niivue_other_tools/RAS.mif");
  DTF_SHARED_FILE(mask, "niivue_other_tools/mask_1bit.mif");
  io::VolumeHeader h;
  const ScalarVolume t = io::readScalarVolume(tmpl.string(), &h);
  EXPECT_EQ(t.grid.dims, glm::ivec3(96, 96, 60));
  // Oblique: the header's transform rows times vox 2.5.
  EXPECT_NEAR(t.grid.voxelToWorld[0][0], 0.99945 * 2.5, 1e-9);
  EXPECT_NEAR(t.grid.voxelToWorld[2][0], -0.0331552 * 2.5, 1e-9);
  EXPECT_NEAR(t.grid.voxelToWorld[1][2], 0.0732382 * 2.5, 1e-9);
  EXPECT_NEAR(t.grid.voxelToWorld[3][1], -92.4614, 1e-9);
  EXPECT_NEAR(t.grid.spacing.x, 2.5, 1e-4);
  EXPECT_EQ(h.datatypeName, "Float32LE");
  EXPECT_GT(*std::max_element(t.data.begin(), t.data.end()), 0.0f);

  const ScalarVolume r = io::readScalarVolume(ras.string(), &h);
  EXPECT_EQ(r.grid.dims, glm::ivec3(64, 79, 67));
  EXPECT_NEAR(r.grid.spacing.y, 2.38975, 1e-6);
  EXPECT_EQ(h.datatypeName, "UInt8");
  // uint8 with scaling 0,0.362956: every value is a whole multiple of the scale, up to 255 of them.
  float hi = 0;
  for (float v : r.data) {
    const double steps = v / 0.362956;
    ASSERT_NEAR(steps, std::round(steps), 1e-3);
    hi = std::max(hi, v);
  }
  EXPECT_GT(hi, 0.362956f * 100);
  EXPECT_LE(hi, 0.362956f * 255 + 1e-3f);

  const ScalarVolume m = io::readScalarVolume(mask.string(), &h);
  EXPECT_EQ(h.datatypeName, "Bit");
  EXPECT_EQ(m.grid.dims, glm::ivec3(96, 96, 60));
  std::size_t set = 0, runs = 0;
  for (int k = 0; k < 60; ++k)
    for (int j = 0; j < 96; ++j)
      for (int i = 0; i < 96; ++i) {
        if (m.at(i, j, k) == 0) continue;
        ASSERT_EQ(m.at(i, j, k), 1.0f);
        ++set;
        if (i + 1 < 96 && m.at(i + 1, j, k) != 0) ++runs;
      }
  // Counted independently from the file's bytes (MRtrix packs the first voxel in the top bit).
  EXPECT_EQ(set, 112138u);
  // A brain mask is compact along i; reading the bits in the wrong order would break runs every byte
  // (0.926 of set voxels continue along i that way against 0.970 the right way).
  EXPECT_GT(double(runs) / double(set), 0.95);
  // Oblique transform, stored with layout -0: orientation and world position of the first voxel.
  EXPECT_NEAR(m.grid.voxelToWorld[3][0], -111.020295121245, 1e-9);
}

// ---------------------------------------------------------------- FSL dtifit

namespace {

// Writes <dir>/dti_V1..V3, L1..L3, FA from a world field, in FSL's frame (voxel axes, x negated when
// det(affine) > 0): v_fsl = (R F)^T v_world.
void writeDtifitSet(const fs::path& dir, const TensorField& field) {
  glm::dmat3 rf = field.grid.rotation();
  if (glm::determinant(glm::dmat3(field.grid.voxelToWorld)) > 0) rf[0] = -rf[0];
  std::vector<ScalarVolume> v(3, ScalarVolume(field.grid, 3)), l(3, ScalarVolume(field.grid, 1));
  ScalarVolume fa(field.grid, 1);
  for (std::size_t i = 0; i < field.tensors.size(); ++i) {
    if (!field.valid[i]) continue;
    const EigenSystem e = eigenDecompose(field.tensors[i]);
    for (int n = 0; n < 3; ++n) {
      const glm::dvec3 f = glm::transpose(rf) * e.vectors[n];
      for (int c = 0; c < 3; ++c)
        v[static_cast<std::size_t>(n)].data[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(f[c]);
      l[static_cast<std::size_t>(n)].data[i] = static_cast<float>(e.values[n]);
    }
    fa.data[i] = static_cast<float>(computeMetrics(e).fa);
  }
  for (int n = 0; n < 3; ++n) {
    io::writeScalarVolume((dir / ("dti_V" + std::to_string(n + 1) + ".nii.gz")).string(),
                          v[static_cast<std::size_t>(n)]);
    io::writeScalarVolume((dir / ("dti_L" + std::to_string(n + 1) + ".nii.gz")).string(),
                          l[static_cast<std::size_t>(n)]);
  }
  io::writeScalarVolume((dir / "dti_FA.nii.gz").string(), fa);
}

} // namespace

TEST(DtifitSet, EigenSystemsGiveBackTheWorldTensor) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  io::LoadedTensors ref = realFslTensor();
  // The real grid is LAS (det < 0); the same world tensors on an RAS grid exercise the x negation.
  TensorField ras = ref.field;
  ras.grid.voxelToWorld[0] = -ras.grid.voxelToWorld[0];
  const fs::path scratch = test::scratchDir();
  for (const TensorField* field : {&ref.field, &ras}) {
    const fs::path dir = scratch / (field == &ras ? "ras" : "las");
    fs::create_directories(dir);
    writeDtifitSet(dir, *field);
    for (const std::string input : {"dti", "dti_V2.nii.gz", "dti_FA.nii.gz"}) {
      SCOPED_TRACE(dir.filename().string() + "/" + input);
      const std::string p = (dir / input).string();
      EXPECT_EQ(io::dtifitSetOf(p), (dir / "dti").string());
      const io::LoadedTensors back = io::readTensorVolume(p);
      EXPECT_NE(back.layoutReason.find("found V1, V2, V3, L1, L2, L3"), std::string::npos)
          << back.layoutReason;
      EXPECT_NE(back.layoutReason.find("FA"), std::string::npos) << back.layoutReason;
      const WorldCompare c = compareInWorld(*field, back.field);
      EXPECT_EQ(c.offGrid, 0u);
      EXPECT_EQ(c.validityMismatch, 0u);
      // float32 eigenvectors and eigenvalues on disk, float32 tensors in memory.
      EXPECT_LT(c.maxRelDiff, 2e-5);
    }
  }
  // A member file is still an ordinary scalar volume for the scalar readers.
  EXPECT_EQ(io::readScalarVolume((scratch / "las" / "dti_FA.nii.gz").string()).components, 1);
}

// V1 without L1-L3 is a one-population fibre set (amplitude 1, FA paired) in FSL's frame; the tensor reader
// still refuses it, pointing at the fibre-set readers.
TEST(DtifitSet, V1OnlySetReadsAsOneFibrePopulationInTheFslFrame) {
  io::LoadedTensors ref = realFslTensor();
  TensorField ras = ref.field;
  ras.grid.voxelToWorld[0] = -ras.grid.voxelToWorld[0];
  const fs::path scratch = test::scratchDir();
  for (const TensorField* field : {&ref.field, &ras}) {
    SCOPED_TRACE(field == &ras ? "RAS grid (det > 0)" : "LAS grid (det < 0)");
    const fs::path dir = scratch / (field == &ras ? "ras" : "las");
    fs::create_directories(dir);
    writeDtifitSet(dir, *field);
    for (const char* m : {"V2", "V3", "L1", "L2", "L3"})
      fs::remove(dir / ("dti_" + std::string(m) + ".nii.gz"));
    const std::string p = (dir / "dti_V1.nii.gz").string();
    std::string why;
    ASSERT_TRUE(io::looksLikeFibres(p, &why)) << why;
    ASSERT_TRUE(io::looksLikeFibres((dir / "dti").string(), &why)) << why;
    const io::LoadedFibres f = io::readFibres(p);
    EXPECT_EQ(f.layout, io::FibreLayout::DtifitV1);
    ASSERT_EQ(f.set.maxFibres, 1);
    ASSERT_EQ(f.files.size(), 2u);
    EXPECT_NE(f.layoutReason.find("found V1, FA; no L1-L3"), std::string::npos) << f.layoutReason;
    ASSERT_EQ(f.fa.grid.dims, field->grid.dims);
    std::size_t compared = 0;
    double worst = 1;
    for (std::size_t i = 0; i < field->tensors.size(); ++i) {
      if (!field->valid[i]) continue;
      const EigenSystem e = eigenDecompose(field->tensors[i]);
      const Fibre& fb = f.set.fibres[i];
      if (!(fb.amplitude > 0)) continue;
      EXPECT_EQ(fb.amplitude, 1.0f);
      EXPECT_NEAR(f.fa.data[i], computeMetrics(e).fa, 1e-5);
      worst = std::min(worst, std::abs(glm::dot(glm::dvec3(fb.direction), e.vectors[0])));
      ++compared;
    }
    EXPECT_GT(compared, 1000u);
    EXPECT_GT(worst, 0.9999) << "V1 not mapped to the world e1";
  }
  try {
    io::readTensorVolume((scratch / "las" / "dti_V1.nii.gz").string());
    FAIL() << "a V1-only set was read as tensors";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* s : {"found V1, FA", "missing V2, V3, L1, L2, L3", "one-population fibre set"})
      EXPECT_NE(m.find(s), std::string::npos) << s << " missing from: " << m;
  }
}

TEST(DtifitSet, RealV1AndFaSetIsAFibreSetWithItsFa) {
  DTF_SHARED_FILE(v1, "niivue_fsl_dtifit/V1.nii.gz");
  DTF_SHARED_FILE(faFile, "niivue_fsl_dtifit/FA.nii.gz");
  EXPECT_FALSE(io::dtifitSetOf(v1.string()).empty());
  const io::LoadedFibres f = io::readFibres(v1.string());
  EXPECT_EQ(f.layout, io::FibreLayout::DtifitV1);
  const ScalarVolume fa = io::readScalarVolume(faFile.string());
  ASSERT_EQ(f.fa.data.size(), fa.data.size());
  EXPECT_EQ(f.fa.data, fa.data);
  EXPECT_GT(f.set.occupiedVoxels(), 10000u);
  EXPECT_FLOAT_EQ(f.set.maxAmplitude(), 1.0f);
}

TEST(DtifitSet, SetWithNeitherV1NorEigenvaluesIsRefusedNamingTheMissingFiles) {
  const fs::path dir = test::scratchDir();
  writeDtifitSet(dir, realFslTensor().field);
  for (const char* m : {"V1", "V3", "L1", "L2", "L3"})
    fs::remove(dir / ("dti_" + std::string(m) + ".nii.gz"));
  const std::string p = (dir / "dti").string();
  EXPECT_FALSE(io::looksLikeFibres(p));
  try {
    io::readTensorVolume(p);
    FAIL() << "a V2-only set was read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* s : {"found V2, FA", "missing V1, V3, L1, L2, L3", "a tensor needs V1-V3 and L1-L3"})
      EXPECT_NE(m.find(s), std::string::npos) << s << " missing from: " << m;
  }
}

// ---------------------------------------------------------------- NRRD

namespace {

struct NrrdSpec {
  std::string name;
  bool lps = false;
  bool masked = false;
  bool fullMatrix = false; // kind 3D-matrix: 9 values row by row
  bool detached = false;
  bool gzip = false;
  bool bigEndianDouble = false;
  int tensorAxis = 0;    // position of the tensor axis among the 4
  bool swapIJ = false;   // list the j axis before the i axis
  glm::dmat3 frame{1.0}; // measurement frame M (columns)
};

std::string vec(const glm::dvec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "(%.17g,%.17g,%.17g)", v.x, v.y, v.z);
  return b;
}

// Writes `field` as a NRRD tensor file by the format's definition (independent of the reader).
void writeNrrd(const fs::path& dir, const NrrdSpec& s, const TensorField& field) {
  const Grid& g = field.grid;
  const glm::dmat3 S =
      s.lps ? glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)) : glm::dmat3(1.0);
  const int comps = s.fullMatrix ? 9 : s.masked ? 7 : 6;
  // Axis list in file order: spatial axes 0,1,2 (maybe 1,0,2) with the tensor axis inserted.
  std::vector<int> axes = s.swapIJ ? std::vector<int>{1, 0, 2} : std::vector<int>{0, 1, 2};
  axes.insert(axes.begin() + s.tensorAxis, -1);
  std::string sizes, kinds, dirs;
  for (int a : axes) {
    sizes += " " + std::to_string(a < 0 ? comps : g.dims[a]);
    kinds += a < 0 ? (s.fullMatrix ? " 3D-matrix"
                      : s.masked   ? " 3D-masked-symmetric-matrix"
                                   : " 3D-symmetric-matrix")
                   : " space";
    dirs += a < 0 ? " none" : " " + vec(S * glm::dvec3(g.voxelToWorld[a]));
  }
  std::string h = "NRRD0005\n# written by the dtfabric test\ntype: " +
                  std::string(s.bigEndianDouble ? "double" : "float") + "\ndimension: 4\nsizes:" + sizes +
                  "\nkinds:" + kinds +
                  "\nspace: " + (s.lps ? "left-posterior-superior" : "right-anterior-superior") +
                  "\nspace directions:" + dirs + "\nspace origin: " + vec(S * glm::dvec3(g.voxelToWorld[3])) +
                  "\nmeasurement frame: " + vec(s.frame[0]) + " " + vec(s.frame[1]) + " " + vec(s.frame[2]) +
                  "\nendian: " + (s.bigEndianDouble ? "big" : "little") +
                  "\nencoding: " + (s.gzip ? "gzip" : "raw") + "\n";
  // Tensor in the measurement frame: D_mf = M^-1 (S D S) M^-T.
  const glm::dmat3 mi = glm::inverse(s.frame);
  std::string data;
  std::vector<long long> sz;
  for (int a : axes)
    sz.push_back(a < 0 ? comps : g.dims[a]);
  std::vector<int> idx(4, 0);
  const long long total = sz[0] * sz[1] * sz[2] * sz[3];
  for (long long n = 0; n < total; ++n) {
    int ijk[3] = {0, 0, 0}, c = 0;
    for (int p = 0; p < 4; ++p)
      (axes[static_cast<std::size_t>(p)] < 0 ? c : ijk[axes[static_cast<std::size_t>(p)]]) =
          idx[static_cast<std::size_t>(p)];
    const std::size_t vi = g.index(ijk[0], ijk[1], ijk[2]);
    double value = 0;
    if (field.valid[vi]) {
      const glm::dmat3 d = mi * (S * field.tensors[vi].toMat() * S) * glm::transpose(mi);
      const double comp[6] = {d[0][0], d[0][1], d[0][2], d[1][1], d[1][2], d[2][2]};
      value = s.fullMatrix ? d[c % 3][c / 3] : s.masked ? (c == 0 ? 1.0 : comp[c - 1]) : comp[c];
    }
    if (s.bigEndianDouble)
      put<double>(data, value, true);
    else
      put<float>(data, static_cast<float>(value));
    for (int p = 0; p < 4; ++p) {
      if (++idx[static_cast<std::size_t>(p)] < sz[static_cast<std::size_t>(p)]) break;
      idx[static_cast<std::size_t>(p)] = 0;
    }
  }
  if (s.gzip) data = gzipBytes(data);
  if (s.detached) {
    const std::string dataName = s.name + (s.gzip ? ".raw.gz" : ".raw");
    writeBytes(dir / (s.name + ".nhdr"), h + "data file: " + dataName + "\n");
    writeBytes(dir / dataName, data);
  } else {
    writeBytes(dir / (s.name + ".nrrd"), h + "\n" + data);
  }
}

glm::dmat3 rotation(double degZ, double degX) {
  const double a = degZ * M_PI / 180, b = degX * M_PI / 180;
  const glm::dmat3 z(glm::dvec3(std::cos(a), std::sin(a), 0), glm::dvec3(-std::sin(a), std::cos(a), 0),
                     glm::dvec3(0, 0, 1));
  const glm::dmat3 x(glm::dvec3(1, 0, 0), glm::dvec3(0, std::cos(b), std::sin(b)),
                     glm::dvec3(0, -std::sin(b), std::cos(b)));
  return z * x;
}

} // namespace

TEST(NrrdTensor, BothSpacesFramesAndAxisOrdersGiveTheSameWorldTensor) {
  DTF_SHARED_FILE(fsl, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  const io::LoadedTensors ref = realFslTensor();
  const fs::path dir = test::scratchDir();
  std::vector<NrrdSpec> specs;
  {
    NrrdSpec s;
    s.name = "ras_masked_first";
    s.masked = true;
    s.frame = rotation(30, 20);
    specs.push_back(s);
  }
  {
    NrrdSpec s;
    s.name = "lps_detached_gz_last_bigdouble";
    s.lps = true;
    s.detached = true;
    s.gzip = true;
    s.bigEndianDouble = true;
    s.tensorAxis = 3;
    s.frame = rotation(-50, 70);
    specs.push_back(s);
  }
  {
    NrrdSpec s;
    s.name = "lps_swapped_middle_gz";
    s.lps = true;
    s.gzip = true;
    s.tensorAxis = 2;
    s.swapIJ = true;
    s.frame =
        glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)); // Slicer's LPS frame
    specs.push_back(s);
  }
  for (const NrrdSpec& s : specs) {
    SCOPED_TRACE(s.name);
    writeNrrd(dir, s, ref.field);
    const std::string p = (dir / (s.name + (s.detached ? ".nhdr" : ".nrrd"))).string();
    EXPECT_EQ(io::detectFormat(p).format, io::FileFormat::Nrrd);
    const io::LoadedTensors back = io::readTensorVolume(p);
    EXPECT_NE(back.layoutReason.find("measurement frame applied"), std::string::npos) << back.layoutReason;
    EXPECT_EQ(back.field.grid.dims, glm::ivec3(72, 72, 39));
    const WorldCompare c = compareInWorld(ref.field, back.field);
    EXPECT_EQ(c.offGrid, 0u);
    EXPECT_EQ(c.validityMismatch, 0u);
    EXPECT_GT(c.compared, 40000u);
    EXPECT_LT(c.maxRelDiff, 2e-6); // float32 rounding after the frame rotation
  }
  // The measurement frame matters: the same file with an identity frame is far off.
  {
    const auto raw = io::detail::readFileBytes((dir / "ras_masked_first.nrrd").string());
    std::string text(raw.begin(), raw.end());
    const auto at = text.find("measurement frame: ");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, text.find('\n', at) - at, "measurement frame: (1,0,0) (0,1,0) (0,0,1)");
    writeBytes(dir / "no_frame.nrrd", text);
    EXPECT_GT(compareInWorld(ref.field, io::readTensorVolume((dir / "no_frame.nrrd").string()).field).maxDiff,
              1e-4);
  }
}

// A singular (or NaN) measurement frame would flatten every tensor silently, a singular space-directions
// matrix leaves no voxel-to-world affine: both are refused naming the file; a frame that is not a rotation
// is read with a warning.
TEST(NrrdTensor, SingularOrNanFramesAndSpaceDirectionsAreRefused) {
  const fs::path dir = test::scratchDir();
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = 1.5;
  TensorField f = makeTensorField(Grid::fromAffine({4, 3, 2}, a));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    f.tensors[i] = SymTensor::fromMat(glm::dmat3(7e-4) + glm::dmat3(1e-5 * static_cast<double>(i)));
    f.valid[i] = 1;
  }
  const fs::path good = dir / "good.nrrd";
  io::writeTensorVolume(good.string(), f, io::TensorLayout::Auto);
  const auto raw = io::detail::readFileBytes(good.string());
  const std::string text(raw.begin(), raw.end());
  // The file with one header line replaced.
  auto variant = [&](const std::string& name, const std::string& key, const std::string& value) {
    std::string t = text;
    const auto at = t.find(key + ": ");
    EXPECT_NE(at, std::string::npos) << key;
    t.replace(at, t.find('\n', at) - at, key + ": " + value);
    const fs::path p = dir / name;
    writeBytes(p, t);
    return p.string();
  };
  auto refusal = [](const std::string& p) {
    try {
      io::readTensorVolume(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const struct {
    const char* name;
    const char* key;
    const char* value;
    const char* says;
  } cases[] = {
      {"coplanar_frame.nrrd", "measurement frame", "(1,0,0) (0,1,0) (1,1,0)", "singular"},
      {"zero_frame.nrrd", "measurement frame", "(1,0,0) (0,0,0) (0,0,1)", "singular"},
      {"parallel_frame.nrrd", "measurement frame", "(0,0,2) (0,1,0) (0,0,1)", "singular"},
      {"nan_frame.nrrd", "measurement frame", "(nan,0,0) (0,1,0) (0,0,1)", "finite"},
      {"singular_dirs.nrrd", "space directions", "none (1.5,0,0) (0,1.5,0) (3,3,0)", "singular"},
      {"nan_dirs.nrrd", "space directions", "none (1.5,0,0) (0,nan,0) (0,0,1.5)", "finite"},
  };
  for (const auto& c : cases) {
    const std::string p = variant(c.name, c.key, c.value);
    const std::string msg = refusal(p);
    EXPECT_EQ(msg.rfind(p, 0), 0u) << c.name << ": " << msg;
    EXPECT_NE(msg.find(c.says), std::string::npos) << c.name << ": " << msg;
  }
  // Tiny but regular voxels are no singular matrix.
  const std::string tiny = variant("tiny.nrrd", "space directions", "none (0.001,0,0) (0,0.001,0) (0,0,0.001)");
  EXPECT_EQ(refusal(tiny), "");
  // A scaled frame is read, with a warning that it is not a rotation.
  auto notRotation = [](const io::LoadedTensors& t) {
    return std::any_of(t.warnings.begin(), t.warnings.end(),
                       [](const std::string& w) { return w.find("not a rotation") != std::string::npos; });
  };
  EXPECT_TRUE(notRotation(io::readTensorVolume(variant("scaled.nrrd", "measurement frame", "(2,0,0) (0,1,0) (0,0,1)"))));
  EXPECT_FALSE(notRotation(io::readTensorVolume(good.string())));
}

// ---------------------------------------------------------------- DSI Studio

TEST(DsiStudio, FittingTheSrcGivesTheFibsDtiFaAndFirstFibre) {
  DTF_SHARED_FILE(src, "niivue_other_tools/dsistudio.src.gz");
  DTF_SHARED_FILE(fibPath, "niivue_other_tools/dsistudio.fib.gz");
  EXPECT_EQ(io::detectFormat(src.string()).format, io::FileFormat::DsiStudioSrc);
  EXPECT_TRUE(io::hasEmbeddedGradients(src.string()));
  const io::Dwi dwi = io::readDwi(src.string(), "", "");
  ASSERT_EQ(dwi.signal.components, 21);
  const io::DsiStudioFib fib = io::readDsiStudioFib(fibPath.string());
  ASSERT_EQ(fib.fraction.size(), 3u);
  ASSERT_EQ(fib.dtiFa.grid.dims, dwi.signal.grid.dims);
  EXPECT_EQ(fib.grid.orientationCode(), "LPS");
  MaskVolume mask(fib.grid, 1, 0);
  for (std::size_t i = 0; i < mask.data.size(); ++i)
    mask.data[i] = fib.dtiFa.data[i] > 0 ? 1 : 0;
  io::FitOptions fo;
  fo.method = io::FitMethod::Wls;
  const TensorField fit = io::fitTensors(dwi, &mask, fo);
  std::vector<double> a, b, absDiff, cosines;
  for (std::size_t i = 0; i < mask.data.size(); ++i) {
    if (!mask.data[i] || !fit.valid[i]) continue;
    const EigenSystem e = eigenDecompose(fit.tensors[i]);
    const double fa = computeMetrics(e).fa;
    a.push_back(fa);
    b.push_back(fib.dtiFa.data[i]);
    absDiff.push_back(std::abs(fa - fib.dtiFa.data[i]));
    if (fib.dtiFa.data[i] > 0.4 && fib.fraction[0].data[i] > 0) {
      const glm::dvec3 d(fib.directions[0].data[i * 3], fib.directions[0].data[i * 3 + 1],
                         fib.directions[0].data[i * 3 + 2]);
      cosines.push_back(std::abs(glm::dot(d, e.vectors[0])));
    }
  }
  ASSERT_GT(a.size(), 10000u);
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= double(a.size());
  mb /= double(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  const double r = sab / std::sqrt(saa * sbb);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  // Both a correlation and a median difference: DSI Studio fits its DTI maps its own way (not the WLS fit
  // here), so individual voxels differ; the correlation says the maps agree voxel by voxel in pattern, the
  // median |difference| that they agree in scale (a correlation alone would accept FA * 0.5).
  const double medDiff = median(absDiff), medCos = median(cosines);
  std::printf("DSI Studio pair: %zu voxels, FA correlation %.4f, median |FA diff| %.4f; %zu WM voxels, "
              "median |cos(fibre 0, V1)| %.4f\n",
              a.size(), r, medDiff, cosines.size(), medCos);
  EXPECT_GT(r, 0.97);
  EXPECT_LT(medDiff, 0.02);
  ASSERT_GT(cosines.size(), 1000u);
  EXPECT_GT(medCos, 0.97);
}

TEST(Formats, DetectionByContentAndName) {
  const fs::path dir = test::scratchDir();
  writeBytes(dir / "misnamed.nii", "mrtrix image\ndim: 1,1,1\n");
  EXPECT_EQ(io::detectFormat((dir / "misnamed.nii").string()).format, io::FileFormat::Mrtrix);
  writeBytes(dir / "x.mif", "NRRD0004\n");
  const io::FormatGuess g = io::detectFormat((dir / "x.mif").string());
  EXPECT_EQ(g.format, io::FileFormat::Nrrd);
  EXPECT_NE(g.reason.find("NRRD"), std::string::npos);
  EXPECT_EQ(io::detectFormat((dir / "missing.mif.gz").string()).format, io::FileFormat::Mrtrix);
  EXPECT_EQ(io::detectFormat((dir / "missing.nii.gz").string()).format, io::FileFormat::Nifti);
  EXPECT_THROW(io::readHeader((dir / "missing.mif.gz").string()), InputError);
}

TEST(Afni, EigenvectorDatasetLoadsWithItsGeometry) {
  DTF_SHARED_FILE(head, "niivue_other_tools/DT_V1+orig.HEAD");
  io::VolumeHeader h;
  const ScalarVolume v = io::readScalarVolume(head.string(), &h);
  EXPECT_EQ(h.format, "AFNI dataset");
  EXPECT_EQ(v.grid.dims, glm::ivec3(128, 128, 70));
  ASSERT_EQ(v.components, 3);
  // IJK_TO_DICOM_REAL gives LPS (x = 2i - 129.0411, y = -2j + 95.20151, z = 2k - 104.7115); RAS negates x, y.
  const glm::dvec3 w = v.grid.toWorld(glm::dvec3(10, 20, 30));
  EXPECT_NEAR(w.x, -(2 * 10 - 129.0411), 1e-4);
  EXPECT_NEAR(w.y, -(-2 * 20 + 95.20151), 1e-4);
  EXPECT_NEAR(w.z, 2 * 30 - 104.7115, 1e-4);
  EXPECT_EQ(v.grid.orientationCode(), "LAS");
  std::size_t nonzero = 0, unit = 0;
  for (std::size_t i = 0; i < v.grid.voxelCount(); ++i) {
    const glm::dvec3 e(v.data[i * 3], v.data[i * 3 + 1], v.data[i * 3 + 2]);
    if (glm::length(e) == 0) continue;
    ++nonzero;
    unit += std::abs(glm::length(e) - 1) < 1e-3;
  }
  EXPECT_GT(nonzero, 50000u);
  // Unit eigenvectors, as 3dDWItoDT writes them (5 of 168,681 voxels in this file are not).
  EXPECT_GT(double(unit) / double(nonzero), 0.9999);
  EXPECT_THROW(io::readTensorVolume(head.string()), InputError);
}
