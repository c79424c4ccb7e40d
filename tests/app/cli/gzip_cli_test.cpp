// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info` on gzip files as users meet them: several gzip members read as one, a truncated file and
// a deflate bomb (a small file inflating far beyond its header) give exit code 2 and a message naming the file.
#include "io/formats/tensor_io.h"
#include "io/model/tensor_field.h"
#include "support/cli.h"
#include "support/gzip_files.h"
#include "support/test_env.h"

#include <gtest/gtest.h>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

fs::path writeTensors(const fs::path& dir, const std::string& name) {
  glm::dmat4 a(1.0);
  a[0][0] = a[1][1] = a[2][2] = 2.0;
  TensorField f = makeTensorField(Grid::fromAffine({6, 5, 4}, a));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    glm::dmat3 m(3e-4);
    m[0][0] = 1e-3 + 1e-4 * static_cast<double>(i % 7);
    f.tensors[i] = SymTensor::fromMat(m);
    f.valid[i] = 1;
  }
  const fs::path p = dir / name;
  io::writeTensorVolume(p.string(), f, io::TensorLayout::Fsl);
  return p;
}

// `info --json` of `other` is that of `original`, the file's name apart; returns other's description.
std::string expectDescribedAlike(const fs::path& original, const fs::path& other, const fs::path& dir) {
  const test::CliResult a = test::runDtfabric("info '" + original.string() + "' --json", dir);
  const test::CliResult b = test::runDtfabric("info '" + other.string() + "' --json", dir);
  EXPECT_EQ(a.exitCode, 0) << a.err;
  EXPECT_EQ(b.exitCode, 0) << b.err;
  std::string expected = a.out;
  const std::string from = original.string();
  for (auto at = expected.find(from); at != std::string::npos; at = expected.find(from, at + 1))
    expected.replace(at, from.size(), other.string());
  EXPECT_EQ(b.out, expected);
  return b.out;
}

} // namespace

TEST(GzipCli, MultiMemberFileIsDescribedLikeTheOriginal) {
  const fs::path dir = test::scratchDir();
  const fs::path p = writeTensors(dir, "t.nii.gz"), multi = dir / "multi.nii.gz";
  const test::Bytes raw = test::gunzipFile(p);
  test::writeBytes(multi, test::multiMember(raw, {348, raw.size() / 2}));
  const std::string out = expectDescribedAlike(p, multi, dir);
  EXPECT_NE(out.find("valid_voxels"), std::string::npos) << out;
}

TEST(GzipCli, TruncatedAndBombFilesExitTwoNamingTheFile) {
  const fs::path dir = test::scratchDir();
  for (const char* name : {"t.nii.gz", "t.mif.gz"}) {
    const fs::path p = writeTensors(dir, name);
    const test::Bytes raw = test::gunzipFile(p);
    const fs::path bomb = dir / (std::string("bomb_") + name), cut = dir / (std::string("cut_") + name);
    test::writeBytes(bomb, test::bomb(raw, std::size_t(128) << 20));
    test::Bytes b = test::readBytes(p);
    b.resize(b.size() / 2);
    test::writeBytes(cut, b);
    for (const fs::path& bad : {bomb, cut}) {
      const test::CliResult r = test::runDtfabric("info '" + bad.string() + "'", dir);
      EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.out << r.err;
      EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
    }
    const test::CliResult r = test::runDtfabric("info '" + bomb.string() + "'", dir);
    EXPECT_NE(r.err.find("deflate bomb"), std::string::npos) << r.err;
  }
}

// Compression is told from the bytes: plain NIfTI under a .nii.gz name reads as the original; gzip data
// under a .nii name (which nifticlib would parse as raw bytes) is refused with the name to give it.
TEST(GzipCli, CompressionIsToldFromTheContentNotTheName) {
  const fs::path dir = test::scratchDir();
  const fs::path p = writeTensors(dir, "t.nii.gz"), plainGz = dir / "plain.nii.gz",
                 gzNii = dir / "packed.nii";
  test::writeBytes(plainGz, test::gunzipFile(p));
  fs::copy_file(p, gzNii);
  expectDescribedAlike(p, plainGz, dir);
  const test::CliResult c = test::runDtfabric("info '" + gzNii.string() + "'", dir);
  EXPECT_EQ(c.exitCode, 2) << c.out << c.err;
  EXPECT_NE(c.err.find(gzNii.string() +
                       ": the file is gzip-compressed but its name does not end in .gz: rename "
                       "it to " +
                       gzNii.string() + ".gz"),
            std::string::npos)
      << c.err;
}
