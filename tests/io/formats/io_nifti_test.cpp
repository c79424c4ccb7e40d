// SPDX-License-Identifier: GPL-3.0-or-later
// NIfTI readers and writers: layout round trips in LAS/RAS/oblique frames, NIfTI-1/2, .nii/.nii.gz;
// the on-disk frame conventions against hand-built files; layout detection; datatypes and scaling;
// malformed files; and the real brain tensors in FSL, SYMMATRIX and MRtrix layouts (shared data).
#include "io/model/error.h"
#include "io/model/tensor.h"
#include "io/formats/tensor_io.h"
#include "support/test_env.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <gtest/gtest.h>
#include <nifti2_io.h>
#include <random>

using namespace dtf;
namespace fs = std::filesystem;

namespace {

glm::dmat4 lasAffine() {
  // The real DWI's sform: LAS, det < 0.
  glm::dmat4 a(1.0);
  a[0][0] = -3;
  a[1][1] = 3;
  a[2][2] = 3;
  a[3] = glm::dvec4(108, -98.279, -23.396, 1);
  return a;
}

glm::dmat4 rasAffine() {
  glm::dmat4 a(1.0);
  a[0][0] = 2;
  a[1][1] = 2.5;
  a[2][2] = 3;
  a[3] = glm::dvec4(-10, 20, -30, 1);
  return a;
}

glm::dmat4 obliqueAffine() {
  // LPS-ish with a 20 degree rotation about z and anisotropic voxels (det < 0).
  double c = std::cos(0.349), s = std::sin(0.349);
  glm::dmat4 a(1.0);
  a[0] = glm::dvec4(-2 * c, -2 * s, 0, 0);
  a[1] = glm::dvec4(-2.5 * s, 2.5 * c, 0, 0);
  a[2] = glm::dvec4(0, 0, -3, 0);
  a[3] = glm::dvec4(5, -7, 40, 1);
  return a;
}

// A field of random positive-definite world tensors (eigenvalues 1e-4..2e-3 mm^2/s); voxel 0 invalid.
TensorField randomField(const glm::dmat4& affine, unsigned seed = 1) {
  TensorField f = makeTensorField(Grid::fromAffine({5, 4, 3}, affine));
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> l(1e-4, 2e-3);
  for (std::size_t i = 1; i < f.tensors.size(); ++i) {
    glm::dvec3 a = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
    glm::dvec3 b = glm::normalize(glm::cross(a, glm::dvec3(n(rng), n(rng), n(rng))));
    glm::dmat3 r(a, b, glm::cross(a, b));
    glm::dmat3 d(0.0);
    d[0][0] = l(rng), d[1][1] = l(rng), d[2][2] = l(rng);
    f.tensors[i] = SymTensor::fromMat(r * d * glm::transpose(r));
    f.valid[i] = 1;
  }
  return f;
}

double maxAbsDiff(const SymTensor& a, const SymTensor& b) {
  auto x = a.components(), y = b.components();
  double m = 0;
  for (int k = 0; k < 6; ++k)
    m = std::max(m, double(std::abs(x[k] - y[k])));
  return m;
}

void expectSameField(const TensorField& a, const TensorField& b, double tol) {
  ASSERT_EQ(a.tensors.size(), b.tensors.size());
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(a.grid.voxelToWorld[c][r], b.grid.voxelToWorld[c][r], 1e-4);
  for (std::size_t i = 0; i < a.tensors.size(); ++i) {
    EXPECT_EQ(a.valid[i], b.valid[i]) << "voxel " << i;
    EXPECT_LT(maxAbsDiff(a.tensors[i], b.tensors[i]), tol) << "voxel " << i;
  }
}

std::vector<char> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void writeBytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
}

template <typename T> void patch(std::vector<char>& bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

// Writes raw components (disk order given per voxel) as a plain float 4D/5D volume, bypassing the tensor
// writer, so the frame conventions are checked against hand-built files.
void writeRaw(const fs::path& p, const Grid& g, const std::vector<std::array<float, 6>>& voxels) {
  ScalarVolume v(g, 6);
  for (std::size_t i = 0; i < voxels.size(); ++i)
    for (int c = 0; c < 6; ++c)
      v.data[i * 6 + c] = voxels[i][static_cast<std::size_t>(c)];
  io::writeScalarVolume(p.string(), v);
}

// Writes a 3D volume of `datatype` with values 0..n-1 through nifticlib.
void writeTyped(const fs::path& p, int datatype, double slope = 1, double inter = 0) {
  int64_t dims[8] = {3, 4, 3, 2, 1, 1, 1, 1};
  nifti_image* nim = nifti_make_new_nim(dims, datatype, 1);
  ASSERT_NE(nim, nullptr);
  for (int64_t i = 0; i < nim->nvox; ++i) {
    switch (datatype) {
    case DT_UINT8:
      static_cast<uint8_t*>(nim->data)[i] = static_cast<uint8_t>(i);
      break;
    case DT_INT16:
      static_cast<int16_t*>(nim->data)[i] = static_cast<int16_t>(i - 5);
      break;
    case DT_UINT16:
      static_cast<uint16_t*>(nim->data)[i] = static_cast<uint16_t>(i + 60000);
      break;
    case DT_INT32:
      static_cast<int32_t*>(nim->data)[i] = static_cast<int32_t>(i * 1000);
      break;
    case DT_FLOAT64:
      static_cast<double*>(nim->data)[i] = 0.25 * static_cast<double>(i);
      break;
    default:
      break;
    }
  }
  nim->scl_slope = slope;
  nim->scl_inter = inter;
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  ASSERT_EQ(nifti_set_filenames(nim, p.string().c_str(), 0, 1), 0);
  nim->nifti_type = NIFTI_FTYPE_NIFTI1_1;
  nifti_image_write(nim);
  nifti_image_free(nim);
}

// Expects an InputError whose message names `path` and contains `fragment`.
template <typename F> void expectInputError(F&& fn, const fs::path& path, const std::string& fragment) {
  try {
    fn();
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << msg;
  }
}

} // namespace

TEST(IoLayout, NamesParseBack) {
  for (auto l : {io::TensorLayout::Auto, io::TensorLayout::Fsl, io::TensorLayout::Mrtrix,
                 io::TensorLayout::Symmatrix, io::TensorLayout::Dtitk})
    EXPECT_EQ(io::parseLayout(io::layoutName(l)), l);
  EXPECT_THROW(io::parseLayout("bogus"), UsageError);
}

// Every layout x frame x file kind x NIfTI version: write, read back (explicitly and auto), same world
// tensors.
TEST(IoRoundTrip, EveryLayoutFrameAndFileKind) {
  auto dir = test::scratchDir();
  const std::pair<const char*, glm::dmat4> frames[] = {
      {"las", lasAffine()}, {"ras", rasAffine()}, {"oblique", obliqueAffine()}};
  for (auto layout : {io::TensorLayout::Fsl, io::TensorLayout::Mrtrix, io::TensorLayout::Symmatrix,
                      io::TensorLayout::Dtitk})
    for (const auto& [frameName, affine] : frames)
      for (const char* ext : {".nii", ".nii.gz"})
        for (int version : {1, 2}) {
          SCOPED_TRACE(std::string(io::layoutName(layout)) + " " + frameName + ext + " v" +
                       std::to_string(version));
          TensorField f = randomField(affine);
          auto path = dir / (std::string(io::layoutName(layout)) + "_" + frameName + "_v" +
                             std::to_string(version) + ext);
          io::writeTensorVolume(path.string(), f, layout, version);
          io::VolumeHeader h = io::readHeader(path.string());
          EXPECT_EQ(h.niftiVersion, version);
          EXPECT_EQ(h.qformCode, 1);
          EXPECT_EQ(h.sformCode, 1);
          EXPECT_TRUE(h.warnings.empty()) << h.warnings.front(); // qform agrees with sform
          bool sym = layout == io::TensorLayout::Symmatrix || layout == io::TensorLayout::Dtitk;
          EXPECT_EQ(h.dims.size(), sym ? 5u : 4u);
          EXPECT_EQ(h.intentCode, sym ? 1005 : 0);
          if (sym) { // the standard's intent_p1 of SYMMATRIX: N of the N x N matrices (read by nifticlib)
            nifti_image* nim = nifti_image_read(path.string().c_str(), 0);
            ASSERT_TRUE(nim);
            EXPECT_EQ(nim->intent_p1, 3.0);
            nifti_image_free(nim);
          }
          for (auto asked : {layout, io::TensorLayout::Auto}) {
            io::LoadedTensors t = io::readTensorVolume(path.string(), asked);
            EXPECT_EQ(t.layout, layout);
            EXPECT_FALSE(t.layoutReason.empty());
            // float32 on disk: ~1e-7 relative of values up to 2e-3.
            expectSameField(f, t.field, 1e-9);
            EXPECT_EQ(t.nanVoxels, 0u);
            EXPECT_EQ(t.nonPositiveVoxels, 0u);
          }
        }
}

// FSL/bvec frame by hand: with LAS (det < 0) the frame is the voxel axes, world = R D R^T with
// R = diag(-1, 1, 1); with RAS (det > 0) FSL flips x, so the same disk tensor maps to the same world
// tensor. Either way the world xy and xz are the negated disk values here.
TEST(IoFrames, FslDiskTensorToWorldByHand) {
  auto dir = test::scratchDir();
  const std::array<float, 6> disk = {1.5e-3f, 2e-4f, -3e-4f, 5e-4f, 1e-4f, 4e-4f}; // xx xy xz yy yz zz
  for (const auto& affine : {lasAffine(), rasAffine()}) {
    Grid g = Grid::fromAffine({2, 2, 2}, affine);
    auto path = dir / "hand_fsl.nii";
    writeRaw(path, g, std::vector<std::array<float, 6>>(8, disk));
    io::LoadedTensors t = io::readTensorVolume(path.string(), io::TensorLayout::Fsl);
    const SymTensor& w = t.field.at(1, 1, 1);
    EXPECT_FLOAT_EQ(w.xx, 1.5e-3f);
    EXPECT_FLOAT_EQ(w.xy, -2e-4f);
    EXPECT_FLOAT_EQ(w.xz, 3e-4f);
    EXPECT_FLOAT_EQ(w.yy, 5e-4f);
    EXPECT_FLOAT_EQ(w.yz, 1e-4f);
    EXPECT_FLOAT_EQ(w.zz, 4e-4f);
  }
}

// MRtrix stores world tensors as xx yy zz xy xz yz: no rotation, whatever the affine.
TEST(IoFrames, MrtrixDiskOrderIsWorld) {
  auto dir = test::scratchDir();
  const std::array<float, 6> disk = {1.5e-3f, 5e-4f, 4e-4f, 2e-4f, -3e-4f, 1e-4f}; // xx yy zz xy xz yz
  Grid g = Grid::fromAffine({2, 2, 2}, obliqueAffine());
  auto path = dir / "hand_mrtrix.nii.gz";
  writeRaw(path, g, std::vector<std::array<float, 6>>(8, disk));
  io::LoadedTensors t = io::readTensorVolume(path.string(), io::TensorLayout::Mrtrix);
  const SymTensor& w = t.field.at(0, 1, 0);
  EXPECT_FLOAT_EQ(w.xx, 1.5e-3f);
  EXPECT_FLOAT_EQ(w.yy, 5e-4f);
  EXPECT_FLOAT_EQ(w.zz, 4e-4f);
  EXPECT_FLOAT_EQ(w.xy, 2e-4f);
  EXPECT_FLOAT_EQ(w.xz, -3e-4f);
  EXPECT_FLOAT_EQ(w.yz, 1e-4f);
}

// Auto-detection without dtfabric's descrip marker: from which volumes form positive semi-definite tensors.
TEST(IoDetect, FslVersusMrtrixOrderFromData) {
  auto dir = test::scratchDir();
  TensorField f = randomField(rasAffine(), 7);
  std::vector<std::array<float, 6>> fsl, mrtrix;
  for (const auto& t : f.tensors) {
    fsl.push_back({t.xx, t.xy, t.xz, t.yy, t.yz, t.zz}); // RAS: FSL frame = world with x flipped
    fsl.back()[1] = -t.xy;
    fsl.back()[2] = -t.xz;
    mrtrix.push_back({t.xx, t.yy, t.zz, t.xy, t.xz, t.yz});
  }
  writeRaw(dir / "fsl.nii", f.grid, fsl);
  writeRaw(dir / "mrtrix.nii", f.grid, mrtrix);
  io::LoadedTensors a = io::readTensorVolume((dir / "fsl.nii").string());
  io::LoadedTensors b = io::readTensorVolume((dir / "mrtrix.nii").string());
  EXPECT_EQ(a.layout, io::TensorLayout::Fsl) << a.layoutReason;
  EXPECT_EQ(b.layout, io::TensorLayout::Mrtrix) << b.layoutReason;
  EXPECT_NE(a.layoutReason.find("positive"), std::string::npos) << a.layoutReason;
  expectSameField(f, a.field, 1e-9);
  expectSameField(f, b.field, 1e-9);
}

// SYMMATRIX values of ~0.5 (1e-3 mm^2/s units) are detected as DTI-TK and scaled; values ~5e-4 are not.
TEST(IoDetect, DtitkScaleFromMedianTrace) {
  auto dir = test::scratchDir();
  TensorField f = randomField(lasAffine(), 3);
  io::writeTensorVolume((dir / "dtitk.nii").string(), f, io::TensorLayout::Dtitk);
  // Blank the descrip marker so that detection has to use the values.
  for (const char* name : {"dtitk.nii"}) {
    auto bytes = readBytes(dir / name);
    std::fill(bytes.begin() + 148, bytes.begin() + 228, '\0');
    writeBytes(dir / name, bytes);
  }
  io::LoadedTensors t = io::readTensorVolume((dir / "dtitk.nii").string());
  EXPECT_EQ(t.layout, io::TensorLayout::Dtitk) << t.layoutReason;
  EXPECT_NE(t.layoutReason.find("1e-3"), std::string::npos) << t.layoutReason;
  expectSameField(f, t.field, 1e-9);

  io::writeTensorVolume((dir / "sym.nii").string(), f, io::TensorLayout::Symmatrix);
  auto bytes = readBytes(dir / "sym.nii");
  std::fill(bytes.begin() + 148, bytes.begin() + 228, '\0');
  writeBytes(dir / "sym.nii", bytes);
  io::LoadedTensors s = io::readTensorVolume((dir / "sym.nii").string());
  EXPECT_EQ(s.layout, io::TensorLayout::Symmatrix) << s.layoutReason;
  EXPECT_NE(s.layoutReason.find("1005"), std::string::npos) << s.layoutReason;
}

TEST(IoScalar, MultiComponentRoundTripAndNifti2) {
  auto dir = test::scratchDir();
  ScalarVolume v(Grid::fromAffine({3, 4, 5}, obliqueAffine()), 3);
  for (std::size_t i = 0; i < v.data.size(); ++i)
    v.data[i] = 0.5f * static_cast<float>(i) - 7;
  for (int version : {1, 2})
    for (const char* ext : {".nii", ".nii.gz"}) {
      auto p = dir / ("v" + std::to_string(version) + ext);
      io::writeScalarVolume(p.string(), v, version);
      io::VolumeHeader h;
      ScalarVolume r = io::readScalarVolume(p.string(), &h);
      EXPECT_EQ(h.niftiVersion, version);
      EXPECT_EQ(r.components, 3);
      EXPECT_EQ(r.data, v.data);
      EXPECT_EQ(h.grid.orientationCode(), v.grid.orientationCode());
    }
}

// x.nii and x.nii.gz side by side: each read returns its own data (nifticlib alone reads x.nii for both).
TEST(IoScalar, SiblingNiiAndNiiGzAreNotConfused) {
  auto dir = test::scratchDir();
  ScalarVolume a(Grid::fromAffine({2, 2, 2}, rasAffine()), 1, 1.0f), b(a.grid, 1, 2.0f);
  io::writeScalarVolume((dir / "x.nii").string(), a);
  io::writeScalarVolume((dir / "x.nii.gz").string(), b);
  EXPECT_EQ(io::readScalarVolume((dir / "x.nii").string()).data, a.data);
  EXPECT_EQ(io::readScalarVolume((dir / "x.nii.gz").string()).data, b.data);
}

TEST(IoScalar, IntegerAndDoubleDatatypesWithScaling) {
  auto dir = test::scratchDir();
  struct Case {
    int dt;
    double slope, inter;
    float expect3; // value of element 3 after scaling
  } cases[] = {{DT_UINT8, 1, 0, 3.0f},
               {DT_INT16, 0.5, 1, (3 - 5) * 0.5f + 1},
               {DT_UINT16, 0, 7, 60003.0f},
               {DT_INT32, 2, 0, 6000.0f},
               {DT_FLOAT64, 1, 0, 0.75f}};
  for (const auto& c : cases) {
    SCOPED_TRACE(nifti_datatype_to_string(c.dt));
    auto p = dir / ("t" + std::to_string(c.dt) + ".nii");
    writeTyped(p, c.dt, c.slope, c.inter);
    ScalarVolume v = io::readScalarVolume(p.string());
    ASSERT_EQ(v.data.size(), 24u);
    EXPECT_FLOAT_EQ(v.data[3], c.expect3); // slope 0 means no scaling (UINT16 case)
  }
}

TEST(IoHeader, SformPreferredAndDisagreementWarned) {
  auto dir = test::scratchDir();
  ScalarVolume v(Grid::fromAffine({2, 2, 2}, rasAffine()), 1, 1.0f);
  auto p = dir / "a.nii";
  io::writeScalarVolume(p.string(), v);
  auto bytes = readBytes(p);
  // srow_x[3] (NIfTI-1 offset 280 + 12): move the sform 5 mm along x.
  patch<float>(bytes, 292, -5.0f);
  writeBytes(p, bytes);
  io::VolumeHeader h = io::readHeader(p.string());
  EXPECT_EQ(h.affineSource, "sform");
  EXPECT_DOUBLE_EQ(h.grid.voxelToWorld[3][0], -5.0);
  ASSERT_EQ(h.warnings.size(), 1u);
  EXPECT_NE(h.warnings[0].find("disagree"), std::string::npos);
  // sform_code 0 (offset 254): the qform is used.
  patch<int16_t>(bytes, 254, 0);
  writeBytes(p, bytes);
  h = io::readHeader(p.string());
  EXPECT_EQ(h.affineSource, "qform");
  EXPECT_NEAR(h.grid.voxelToWorld[3][0], -10.0, 1e-5);
  EXPECT_TRUE(h.warnings.empty());
}

TEST(IoErrors, MalformedFilesThrowInputErrorNamingTheFile) {
  auto dir = test::scratchDir();
  TensorField f = randomField(lasAffine(), 5);
  // Random tensors so the gzip stream is long enough to truncate and corrupt meaningfully.
  f = makeTensorField(Grid::fromAffine({20, 20, 20}, lasAffine()));
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(1e-4f, 1e-3f);
  for (std::size_t i = 0; i < f.tensors.size(); ++i)
    f.tensors[i] = {u(rng), 0, 0, u(rng), 0, u(rng)}, f.valid[i] = 1;
  auto good = dir / "good.nii.gz";
  io::writeTensorVolume(good.string(), f, io::TensorLayout::Fsl);

  expectInputError([&] { io::readTensorVolume((dir / "missing.nii.gz").string()); }, dir / "missing.nii.gz",
                   "does not exist");

  auto bytes = readBytes(good);
  auto truncated = dir / "truncated.nii.gz";
  writeBytes(truncated,
             std::vector<char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size() / 2)));
  expectInputError([&] { io::readTensorVolume(truncated.string()); }, truncated, "truncated");

  auto corrupt = dir / "corrupt.nii.gz";
  auto c = bytes;
  for (std::size_t i = c.size() / 3; i < c.size() / 3 + 64; ++i)
    c[i] = static_cast<char>(0x5a ^ c[i]);
  writeBytes(corrupt, c);
  expectInputError([&] { io::readTensorVolume(corrupt.string()); }, corrupt, "gzip");

  auto header = dir / "badgzip.nii.gz";
  c = bytes;
  for (std::size_t i = 10; i < 40; ++i)
    c[i] = 0x33; // inside the deflate stream of the header
  writeBytes(header, c);
  expectInputError([&] { io::readHeader(header.string()); }, header, "NIfTI");

  // Uncompressed, cut short: refused from the header before reading.
  auto plain = dir / "plain.nii";
  io::writeTensorVolume(plain.string(), f, io::TensorLayout::Fsl);
  auto p = readBytes(plain);
  ASSERT_GT(p.size(), 1000u);
  writeBytes(plain, std::vector<char>(p.begin(), p.end() - 100));
  expectInputError([&] { io::readHeader(plain.string()); }, plain, "truncated");
}

TEST(IoErrors, ShapeDatatypeAndAbsurdDims) {
  auto dir = test::scratchDir();
  Grid g = Grid::fromAffine({3, 3, 3}, rasAffine());
  // 5 volumes are not a tensor.
  auto five = dir / "five.nii";
  io::writeScalarVolume(five.string(), ScalarVolume(g, 5, 1.0f));
  expectInputError([&] { io::readTensorVolume(five.string()); }, five, "not a tensor volume");
  // 7-D with 6 values per voxel spread over dims 5..7.
  auto six = dir / "seven.nii";
  io::writeScalarVolume(six.string(), ScalarVolume(g, 6, 1.0f));
  auto b = readBytes(six);
  const int16_t dims7[8] = {7, 3, 3, 3, 1, 2, 3, 1};
  std::memcpy(b.data() + 40, dims7, sizeof(dims7));
  writeBytes(six, b);
  EXPECT_EQ(io::readHeader(six.string()).dims.size(), 7u);
  expectInputError([&] { io::readTensorVolume(six.string(), io::TensorLayout::Fsl); }, six,
                   "not a tensor volume");
  // COMPLEX64 (datatype 32, bitpix 64).
  auto cplx = dir / "complex.nii";
  io::writeScalarVolume(cplx.string(), ScalarVolume(g, 2, 1.0f));
  b = readBytes(cplx);
  patch<int16_t>(b, 70, 32);
  patch<int16_t>(b, 72, 64);
  const int16_t dims3[8] = {3, 3, 3, 3, 1, 1, 1, 1};
  std::memcpy(b.data() + 40, dims3, sizeof(dims3));
  writeBytes(cplx, b);
  expectInputError([&] { io::readScalarVolume(cplx.string()); }, cplx, "unsupported datatype");
  // NIfTI-2 header declaring 100000^3 voxels in a tiny file: refused before allocating.
  auto huge = dir / "huge.nii";
  io::writeScalarVolume(huge.string(), ScalarVolume(g, 1, 1.0f), 2);
  b = readBytes(huge);
  for (int d = 1; d <= 3; ++d)
    patch<int64_t>(b, 16 + 8 * static_cast<std::size_t>(d), 100000);
  writeBytes(huge, b);
  expectInputError([&] { io::readScalarVolume(huge.string()); }, huge, "absurd");
  // A dimension of 0.
  auto zero = dir / "zero.nii";
  io::writeScalarVolume(zero.string(), ScalarVolume(g, 1, 1.0f));
  b = readBytes(zero);
  patch<int16_t>(b, 42, 0);
  writeBytes(zero, b);
  EXPECT_THROW(io::readScalarVolume(zero.string()), InputError);
}

// A .nii.gz of a few kB whose header declares 4 GB: the reader grows its buffer with the inflated data,
// so it fails on the short stream instead of allocating the declared size first.
TEST(IoErrors, SmallGzipDeclaringGigabytesFailsCleanly) {
  auto dir = test::scratchDir();
  auto plain = dir / "small.nii";
  io::writeScalarVolume(plain.string(), ScalarVolume(Grid::fromAffine({8, 8, 8}, rasAffine()), 1, 1.0f));
  auto b = readBytes(plain);
  const int16_t dims[8] = {3, 1000, 1000, 1000, 1, 1, 1, 1};
  std::memcpy(b.data() + 40, dims, sizeof(dims));
  auto gz = dir / "declares4gb.nii.gz";
  znzFile fp = znzopen(gz.string().c_str(), "wb", 1);
  ASSERT_FALSE(znz_isnull(fp));
  ASSERT_EQ(znzwrite(b.data(), 1, b.size(), fp), b.size());
  znzclose(fp);
  EXPECT_EQ(io::readHeader(gz.string()).dims[2], 1000); // the header alone is fine
  expectInputError([&] { io::readScalarVolume(gz.string()); }, gz, "truncated");
}

TEST(IoErrors, NanVoxelsCountedAndAllNanRefused) {
  auto dir = test::scratchDir();
  TensorField f = randomField(rasAffine(), 9);
  f.tensors[5].xy = NAN;
  f.tensors[6].zz = INFINITY;
  // The writer writes invalid voxels as zero, so NaN goes in through the raw writer.
  std::vector<std::array<float, 6>> raw;
  for (const auto& t : f.tensors)
    raw.push_back({t.xx, -t.xy, -t.xz, t.yy, t.yz, t.zz});
  auto p = dir / "nan.nii";
  writeRaw(p, f.grid, raw);
  io::LoadedTensors t = io::readTensorVolume(p.string(), io::TensorLayout::Fsl);
  EXPECT_EQ(t.nanVoxels, 2u);
  EXPECT_FALSE(t.field.valid[5]);
  EXPECT_FALSE(t.field.valid[6]);
  EXPECT_TRUE(t.field.at(0, 0, 0).isZero());
  EXPECT_TRUE(t.field.tensors[5].isZero());
  EXPECT_TRUE(t.field.valid[7]);
  auto allNan = dir / "allnan.nii";
  writeRaw(allNan, f.grid, std::vector<std::array<float, 6>>(f.tensors.size(), {NAN, 0, 0, NAN, 0, NAN}));
  expectInputError([&] { io::readTensorVolume(allNan.string()); }, allNan, "NaN");
}

TEST(IoErrors, NonPositiveDefiniteCounted) {
  auto dir = test::scratchDir();
  TensorField f = randomField(rasAffine(), 11);
  f.tensors[3] = {1e-3f, 0, 0, -1e-4f, 0, 1e-3f};
  io::writeTensorVolume((dir / "npd.nii").string(), f, io::TensorLayout::Mrtrix);
  io::LoadedTensors t = io::readTensorVolume((dir / "npd.nii").string());
  EXPECT_EQ(t.nonPositiveVoxels, 1u);
  EXPECT_TRUE(t.field.valid[3]); // finite and non-zero: kept, but counted
}

TEST(IoErrors, WriterRefusesBadNamesAndAutoLayout) {
  auto dir = test::scratchDir();
  TensorField f = randomField(rasAffine());
  EXPECT_THROW(io::writeTensorVolume((dir / "x.img").string(), f, io::TensorLayout::Fsl), InputError);
  EXPECT_THROW(io::writeTensorVolume((dir / "x.nii").string(), f, io::TensorLayout::Auto), InputError);
  EXPECT_THROW(io::writeTensorVolume((dir / "no_such_dir" / "x.nii").string(), f, io::TensorLayout::Fsl),
               InputError);
  EXPECT_FALSE(fs::exists(dir / "x.nii"));
}

// ---- real data (../shared/data) ----

namespace {
const char* kDerived = "iu_prisma_dwi/derived/";

struct Reference {
  glm::ivec3 ijk;
  double fa;
  int axis; // world axis of the principal eigenvector: 0 left-right, 2 superior-inferior
};
const Reference kReferences[] = {{{33, 42, 22}, 0.8463, 0}, {{30, 34, 15}, 0.8206, 2}};

void expectReferenceVoxels(const TensorField& f, double faTol) {
  for (const auto& r : kReferences) {
    EigenSystem e = eigenDecompose(f.at(r.ijk.x, r.ijk.y, r.ijk.z));
    EXPECT_NEAR(computeMetrics(e).fa, r.fa, faTol) << r.ijk.x << "," << r.ijk.y << "," << r.ijk.z;
    EXPECT_GT(std::abs(e.vectors[0][r.axis]), 0.9) << r.ijk.x << "," << r.ijk.y << "," << r.ijk.z;
  }
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    ma += a[i], mb += b[i];
  ma /= double(a.size());
  mb /= double(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}
} // namespace

TEST(IoRealData, AutoDetectsEachLayoutWithAReason) {
  DTF_SHARED_FILE(fsl, std::string(kDerived) + "dti_tensor.nii.gz");
  DTF_SHARED_FILE(mrtrix, std::string(kDerived) + "dti_tensor_mrtrix.nii.gz");
  DTF_SHARED_FILE(sym, std::string(kDerived) + "dti_tensor_symmatrix5d.nii.gz");
  io::LoadedTensors a = io::readTensorVolume(fsl.string());
  io::LoadedTensors b = io::readTensorVolume(mrtrix.string());
  io::LoadedTensors c = io::readTensorVolume(sym.string());
  EXPECT_EQ(a.layout, io::TensorLayout::Fsl) << a.layoutReason;
  EXPECT_EQ(b.layout, io::TensorLayout::Mrtrix) << b.layoutReason;
  EXPECT_EQ(c.layout, io::TensorLayout::Symmatrix) << c.layoutReason;
  EXPECT_NE(a.layoutReason.find("FSL"), std::string::npos) << a.layoutReason;
  EXPECT_NE(c.layoutReason.find("1005"), std::string::npos) << c.layoutReason;
  EXPECT_EQ(a.header.grid.orientationCode(), "LAS");
  EXPECT_EQ(a.header.affineSource, "sform");
  std::size_t valid = 0;
  for (auto v : a.field.valid)
    valid += v;
  EXPECT_EQ(valid, 49040u); // the mask size
  EXPECT_EQ(a.nanVoxels, 0u);
  EXPECT_EQ(b.nanVoxels, 1u); // the b0 = 0 voxel
}

TEST(IoRealData, ReferenceVoxelsInWorldFrame) {
  DTF_SHARED_FILE(fsl, std::string(kDerived) + "dti_tensor.nii.gz");
  DTF_SHARED_FILE(sym, std::string(kDerived) + "dti_tensor_symmatrix5d.nii.gz");
  DTF_SHARED_FILE(mrtrix, std::string(kDerived) + "dti_tensor_mrtrix.nii.gz");
  expectReferenceVoxels(io::readTensorVolume(fsl.string()).field, 0.001);
  expectReferenceVoxels(io::readTensorVolume(sym.string()).field, 0.001);
  expectReferenceVoxels(io::readTensorVolume(mrtrix.string()).field, 0.01); // IWLS, not DIPY's WLS
  // README: world tensor at (33, 42, 22) = R D R^T with R = diag(-1, 1, 1) of the FSL components.
  SymTensor w = io::readTensorVolume(fsl.string()).field.at(33, 42, 22);
  EXPECT_NEAR(w.xx, 1.4692e-3, 1e-7);
  EXPECT_NEAR(w.xy, -1.1027e-4, 1e-8);
  EXPECT_NEAR(w.xz, 3.7012e-4, 1e-8);
  EXPECT_NEAR(w.yz, -2.3325e-5, 1e-9);
}

TEST(IoRealData, FslSymmatrixAndMrtrixGiveTheSameWorldTensors) {
  DTF_SHARED_FILE(fsl, std::string(kDerived) + "dti_tensor.nii.gz");
  DTF_SHARED_FILE(sym, std::string(kDerived) + "dti_tensor_symmatrix5d.nii.gz");
  DTF_SHARED_FILE(mrtrix, std::string(kDerived) + "dti_tensor_mrtrix.nii.gz");
  TensorField a = io::readTensorVolume(fsl.string()).field;
  TensorField b = io::readTensorVolume(sym.string()).field;
  TensorField m = io::readTensorVolume(mrtrix.string()).field;
  // Same numbers in two layouts: identical after conversion.
  for (std::size_t i = 0; i < a.tensors.size(); ++i)
    ASSERT_EQ(maxAbsDiff(a.tensors[i], b.tensors[i]), 0.0) << i;
  // MRtrix (IWLS, world frame) against DIPY WLS (bvec frame): README reports correlations 0.978-0.997 and
  // a median absolute difference of 6.3e-7 mm^2/s once both are in the same frame.
  std::vector<double> ca[6], cm[6], absDiff;
  std::size_t signChecked = 0, signAgree = 0;
  for (std::size_t i = 0; i < a.tensors.size(); ++i) {
    if (!a.valid[i] || !m.valid[i]) continue;
    auto x = a.tensors[i].components(), y = m.tensors[i].components();
    for (int k = 0; k < 6; ++k) {
      ca[k].push_back(x[k]);
      cm[k].push_back(y[k]);
      absDiff.push_back(std::abs(x[k] - y[k]));
    }
    for (int k : {1, 2})
      if (std::abs(x[k]) > 1e-4) ++signChecked, signAgree += (x[k] > 0) == (y[k] > 0);
  }
  ASSERT_GT(absDiff.size(), 6u * 40000u);
  for (int k = 0; k < 6; ++k)
    EXPECT_GT(correlation(ca[k], cm[k]), 0.95) << "component " << k;
  auto mid = absDiff.begin() + static_cast<std::ptrdiff_t>(absDiff.size() / 2);
  std::nth_element(absDiff.begin(), mid, absDiff.end());
  EXPECT_LT(*mid, 2e-6);
  // Without the LAS flip xy and xz would disagree in sign almost everywhere.
  EXPECT_GT(double(signAgree) / double(signChecked), 0.98) << signAgree << "/" << signChecked;
}

TEST(IoRealData, ScalarAndVectorVolumesLoad) {
  DTF_SHARED_FILE(fa, "niivue_fsl_dtifit/FA.nii.gz");
  DTF_SHARED_FILE(v1, "niivue_fsl_dtifit/V1.nii.gz");
  DTF_SHARED_FILE(dwi, "iu_prisma_dwi/dwi.nii.gz");
  DTF_SHARED_FILE(dsi, "dipy_small/small_101D.nii.gz");
  io::VolumeHeader h;
  ScalarVolume f = io::readScalarVolume(fa.string(), &h);
  EXPECT_EQ(f.components, 1);
  EXPECT_EQ(h.grid.dims, glm::ivec3(84, 92, 56));
  EXPECT_NEAR(*std::max_element(f.data.begin(), f.data.end()), 1.2247, 1e-3); // FSL's FA > 1, kept as is
  ScalarVolume v = io::readScalarVolume(v1.string(), &h);
  EXPECT_EQ(v.components, 3);
  EXPECT_EQ(h.intentCode, 2003);
  EXPECT_EQ(h.intentName, "RGB_VECTOR");
  std::size_t unit = 0, nonzero = 0;
  for (std::size_t i = 0; i < v.grid.voxelCount(); ++i) {
    glm::dvec3 e(v.data[i * 3], v.data[i * 3 + 1], v.data[i * 3 + 2]);
    if (glm::length(e) == 0) continue;
    ++nonzero;
    unit += std::abs(glm::length(e) - 1) < 1e-3;
  }
  EXPECT_GT(nonzero, 10000u);
  EXPECT_EQ(unit, nonzero);
  // V1.nii.gz with FA.nii.gz is an FSL dtifit set without eigenvalues: refused naming what is missing.
  expectInputError([&] { io::readTensorVolume(v1.string()); }, v1, "missing V2, V3, L1, L2, L3");
  ScalarVolume d = io::readScalarVolume(dwi.string(), &h);
  EXPECT_EQ(d.components, 21);
  EXPECT_EQ(h.datatypeName, "INT16");
  EXPECT_EQ(io::readScalarVolume(dsi.string(), &h).components, 102);
  EXPECT_EQ(h.datatypeName, "UINT16");
}
