// SPDX-License-Identifier: GPL-3.0-or-later
// The input opener (io/input.h): what each kind of file is opened as, with its reason, and that the readers
// of each kind read what the opener found (compared with the plain readers, which detect the format
// themselves).
#include "io/formats/format_detail.h"
#include "io/input.h"
#include "io/model/error.h"
#include "io/phantoms.h"
#include "support/test_env.h"

#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

io::PhantomOptions small() {
  io::PhantomOptions o;
  o.size = 12;
  return o;
}

io::OpenedInput openFile(const std::string& path, const std::string& layout = "auto", bool fibres = true) {
  io::InputRequest r;
  r.path = path;
  r.layout = layout;
  r.fibres = fibres;
  return io::openInput(r);
}

std::string sampleDwi() {
  return (dtf::test::sourceDir() / "sample_data" / "dwi.nii.gz").string();
}

} // namespace

TEST(InputOpener, TensorVolumeIsReadAsByTheTensorReader) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string path = (dir / "t.nii.gz").string();
  io::writeTensorVolume(path, io::makePhantom("crossing", small()).tensors, io::TensorLayout::Fsl);
  const io::OpenedInput in = openFile(path);
  EXPECT_EQ(in.kind, io::InputKind::Tensors);
  EXPECT_EQ(in.format.format, io::FileFormat::Nifti);
  EXPECT_NE(in.reason.find("tensor volume"), std::string::npos) << in.reason;
  const io::LoadedTensors a = io::readInputTensors(in), b = io::readTensorVolume(path);
  EXPECT_EQ(a.layout, b.layout);
  EXPECT_EQ(a.layoutReason, b.layoutReason);
  ASSERT_EQ(a.field.tensors.size(), b.field.tensors.size());
  EXPECT_EQ(a.field.valid, b.field.valid);
  for (std::size_t i = 0; i < a.field.tensors.size(); ++i)
    EXPECT_EQ(a.field.tensors[i].toMat(), b.field.tensors[i].toMat()) << i;
  EXPECT_THROW(io::readInputDwi(in), InputError);
  EXPECT_THROW(io::readInputFibres(in), InputError);
}

TEST(InputOpener, FibreSetIsFoundWithItsReason) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string path = (dir / "peaks.nii.gz").string();
  io::writeFibres(path, io::makeFibrePhantom("crossing", small()), io::FibreLayout::MrtrixPeaks);
  const io::OpenedInput in = openFile(path);
  EXPECT_EQ(in.kind, io::InputKind::Fibres);
  EXPECT_NE(in.reason.find("dtfabric"), std::string::npos) << in.reason; // its descrip marker
  const io::LoadedFibres f = io::readInputFibres(in);
  EXPECT_EQ(f.layout, io::FibreLayout::MrtrixPeaks);
  EXPECT_EQ(f.set.fibres.size(), io::readFibres(path).set.fibres.size());
  // Named layouts are taken as given.
  const io::OpenedInput named = openFile(path, "dipy-peaks");
  EXPECT_EQ(named.kind, io::InputKind::Fibres);
  EXPECT_EQ(named.fibreLayout, io::FibreLayout::DipyPeaks);
  // Where fibre sets are not an answer, a 6-volume (two-peak) file is left to the tensor reader, which
  // refuses it.
  const io::OpenedInput asTensor = openFile(path, "auto", false);
  EXPECT_EQ(asTensor.kind, io::InputKind::Tensors);
  EXPECT_THROW(io::readInputTensors(asTensor), InputError);
}

TEST(InputOpener, ThreePeakFileIsRefusedWhereOnlyTensorsAreRead) {
  const fs::path dir = dtf::test::scratchDir();
  // Three populations per voxel, directions of every sign, without dtfabric's marker: told apart from a
  // DWI or a tensor by the signs of its volumes.
  const Grid grid = io::makePhantom("constant", small()).tensors.grid;
  FibreSet set = makeFibreSet(grid, 3);
  for (std::size_t v = 0; v < grid.voxelCount(); ++v)
    for (std::size_t k = 0; k < 3; ++k) {
      const double t = static_cast<double>(v * 3 + k);
      set.fibres[v * 3 + k] = {
          glm::normalize(glm::vec3(std::sin(t), std::cos(1.7 * t), std::sin(2.3 * t + 1))), 0.5f};
    }
  const std::string marked = (dir / "marked.nii.gz").string(), plain = (dir / "plain.nii.gz").string();
  io::writeFibres(marked, set, io::FibreLayout::DipyPeaks);
  io::writeScalarVolume(plain, io::readScalarVolume(marked), 1, "peaks");
  const io::OpenedInput in = openFile(plain);
  EXPECT_EQ(in.kind, io::InputKind::Fibres);
  EXPECT_NE(in.reason.find("like fibre peaks"), std::string::npos) << in.reason;
  try {
    openFile(plain, "auto", false);
    FAIL() << "a fibre set opened as tensors";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a fibre set"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(plain), std::string::npos) << e.what();
  }
  // A tensor layout named: the same refusal (the layout says tensors, the content says fibres).
  EXPECT_THROW(openFile(plain, "fsl"), InputError);
}

TEST(InputOpener, DwiWithSiblingGradientFiles) {
  const io::OpenedInput in = openFile(sampleDwi());
  EXPECT_EQ(in.kind, io::InputKind::Dwi);
  EXPECT_FALSE(in.embeddedGradients);
  EXPECT_EQ(in.bval, io::gradientSibling(sampleDwi(), ".bval"));
  EXPECT_TRUE(fs::exists(in.bval));
  EXPECT_TRUE(fs::exists(in.bvec));
  EXPECT_NE(in.reason.find("a DWI with"), std::string::npos) << in.reason;
  const io::Dwi a = io::readInputDwi(in), b = io::readDwi(sampleDwi(), in.bval, in.bvec);
  EXPECT_EQ(a.bvals, b.bvals);
  EXPECT_EQ(a.signal.data, b.signal.data);
  EXPECT_THROW(io::readInputTensors(in), InputError);
}

TEST(InputOpener, DwiWithoutGradientFilesIsAnErrorNamingThem) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string path = (dir / "lonely.nii.gz").string();
  fs::copy_file(sampleDwi(), path);
  try {
    openFile(path);
    FAIL() << "a DWI without gradient files was opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lonely.bval"), std::string::npos) << e.what();
  }
  io::InputRequest half;
  half.path = path;
  half.bval = io::gradientSibling(sampleDwi(), ".bval");
  EXPECT_THROW(io::openInput(half), UsageError);
}

TEST(InputOpener, EmbeddedGradientTable) {
  const fs::path dir = dtf::test::scratchDir();
  const io::Dwi d = io::readDwi(sampleDwi(), io::gradientSibling(sampleDwi(), ".bval"),
                                io::gradientSibling(sampleDwi(), ".bvec"));
  // An MRtrix image with dw_scheme (scanner-frame directions).
  std::vector<std::string> scheme;
  for (std::size_t n = 0; n < d.bvals.size(); ++n) {
    const glm::dvec3 g = d.gradientsWorld[n];
    scheme.push_back("dw_scheme: " + std::to_string(g.x) + "," + std::to_string(g.y) + "," +
                     std::to_string(g.z) + "," + std::to_string(d.bvals[n]));
  }
  const std::string mif = (dir / "dwi.mif").string();
  io::detail::writeMrtrix(mif, d.signal, {}, scheme);
  const io::OpenedInput in = openFile(mif);
  EXPECT_EQ(in.kind, io::InputKind::Dwi);
  EXPECT_TRUE(in.embeddedGradients);
  EXPECT_EQ(in.format.format, io::FileFormat::Mrtrix);
  const io::Dwi e = io::readInputDwi(in);
  ASSERT_EQ(e.bvals.size(), d.bvals.size());
  for (std::size_t n = 0; n < d.bvals.size(); ++n)
    EXPECT_NEAR(glm::length(e.gradientsWorld[n] - d.gradientsWorld[n]), 0.0, 1e-5) << n;
}

TEST(InputOpener, TractogramsOnlyWhenAskedFor) {
  io::InputRequest r;
  r.path = "bundle.tck";
  r.tractograms = true;
  const io::OpenedInput in = io::openInput(r);
  EXPECT_EQ(in.kind, io::InputKind::Tractogram);
  EXPECT_THROW(io::readInputHeader(in), InputError);
  r.tractograms = false;
  EXPECT_THROW(io::openInput(r), InputError); // no such volume
}
