// SPDX-License-Identifier: GPL-3.0-or-later
// gzip through the readers' whole-buffer inflater: round trips of every gzip format (.nii.gz, .mif.gz,
// NRRD gzip encoding, .trk.gz), the same files re-compressed as several gzip members, truncated files and
// deflate bombs (small files that inflate far beyond what their header declares), each refused with an
// InputError naming the file. Streams are made and checked with zlib, independently of libdeflate.
#include "io/formats/gzip.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/model/error.h"
#include "io/model/tensor_field.h"
#include "support/gzip_files.h"
#include "support/test_env.h"

#include <chrono>
#include <cstring>
#include <gtest/gtest.h>

namespace fs = std::filesystem;
using namespace dtf;
using dtf::test::Bytes;

namespace {

// A 7x5x4 LAS field of distinct positive-definite tensors (every component differs per voxel).
TensorField smallField() {
  glm::dmat4 a(1.0);
  a[0][0] = -2.0;
  a[1][1] = 2.0;
  a[2][2] = 2.5;
  a[3] = glm::dvec4(10, -8, 4, 1);
  TensorField f = makeTensorField(Grid::fromAffine({7, 5, 4}, a));
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    const double t = 1e-4 * static_cast<double>(i % 17);
    glm::dmat3 m(0.0);
    m[0][0] = 1.2e-3 + t;
    m[1][1] = 0.5e-3 + 0.5 * t;
    m[2][2] = 0.3e-3;
    m[0][1] = m[1][0] = 1e-4 + 0.1 * t;
    m[1][2] = m[2][1] = -5e-5;
    m[0][2] = m[2][0] = 2e-5 * static_cast<double>(i % 5);
    f.tensors[i] = SymTensor::fromMat(m);
    f.valid[i] = i % 9 != 0;
  }
  return f;
}

void expectSameField(const TensorField& want, const TensorField& got) {
  ASSERT_EQ(want.grid.dims, got.grid.dims);
  std::size_t compared = 0;
  for (std::size_t i = 0; i < want.tensors.size(); ++i) {
    ASSERT_EQ(want.valid[i], got.valid[i]) << "voxel " << i;
    if (!want.valid[i]) continue;
    const auto a = want.tensors[i].components(), b = got.tensors[i].components();
    for (std::size_t c = 0; c < 6; ++c)
      EXPECT_NEAR(a[c], b[c], 1e-9) << "voxel " << i << " component " << c;
    ++compared;
  }
  EXPECT_GT(compared, want.tensors.size() / 2);
}

// The message of the InputError `f` throws, or "" when it throws none.
template <typename F> std::string inputError(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

const char* kTensorNames[] = {"t.nii.gz", "t.mif.gz", "t.nrrd"};

} // namespace

TEST(GzipIo, EveryGzipTensorFormatRoundTrips) {
  const fs::path dir = test::scratchDir();
  const TensorField f = smallField();
  for (const char* name : kTensorNames) {
    const std::string p = (dir / name).string();
    io::writeTensorVolume(p, f, io::TensorLayout::Fsl);
    const Bytes b = test::readBytes(p);
    if (std::string(name) != "t.nrrd") {
      ASSERT_TRUE(b.size() > 2 && b[0] == 0x1f && b[1] == 0x8b) << name;
    }
    SCOPED_TRACE(name);
    expectSameField(f, io::readTensorVolume(p).field);
  }
}

TEST(GzipIo, MultiMemberFilesReadLikeOneMember) {
  const fs::path dir = test::scratchDir();
  const TensorField f = smallField();
  for (const char* name : {"t.nii.gz", "t.mif.gz"}) {
    const fs::path one = dir / name, many = dir / (std::string("multi_") + name);
    io::writeTensorVolume(one.string(), f, io::TensorLayout::Fsl);
    const Bytes raw = test::gunzipFile(one);
    // Cuts inside the header, inside the data and near the end: three or four members.
    test::writeBytes(many, test::multiMember(raw, {100, raw.size() / 2, raw.size() - 7}));
    SCOPED_TRACE(name);
    expectSameField(f, io::readTensorVolume(many.string()).field);
  }
  // NRRD: the attached data after the blank line as three members.
  const fs::path nrrd = dir / "t.nrrd", multi = dir / "multi_t.nrrd";
  io::writeTensorVolume(nrrd.string(), f, io::TensorLayout::Fsl);
  const Bytes all = test::readBytes(nrrd);
  const std::string text(all.begin(), all.end());
  const std::size_t end = text.find("\n\n") + 2;
  const Bytes header(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(end));
  test::writeBytes(dir / "data.gz", Bytes(all.begin() + static_cast<std::ptrdiff_t>(end), all.end()));
  const Bytes data = test::gunzipFile(dir / "data.gz");
  Bytes out = header;
  const Bytes members = test::multiMember(data, {data.size() / 3, 2 * data.size() / 3});
  out.insert(out.end(), members.begin(), members.end());
  test::writeBytes(multi, out);
  expectSameField(f, io::readTensorVolume(multi.string()).field);
}

TEST(GzipIo, TrkGzRoundTripsAndReadsAsSeveralMembers) {
  const fs::path dir = test::scratchDir();
  Polylines lines;
  lines.offsets.push_back(0);
  for (int l = 0; l < 50; ++l) {
    for (int p = 0; p < 20 + l; ++p)
      lines.points.emplace_back(0.5f * static_cast<float>(p) - 5.0f, 0.25f * static_cast<float>(l) - 3.0f,
                                0.1f * static_cast<float>(p * l % 13));
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  const Grid ref = smallField().grid;
  const fs::path p = dir / "t.trk.gz", multi = dir / "multi.trk.gz";
  io::writeTrk(p.string(), lines, ref);
  io::TrkInfo info;
  const Polylines back = io::readTrk(p.string(), &info);
  EXPECT_TRUE(info.gzipped);
  ASSERT_EQ(back.offsets, lines.offsets);
  for (std::size_t i = 0; i < lines.points.size(); ++i)
    ASSERT_LT(glm::length(back.points[i] - lines.points[i]), 1e-4f) << "point " << i;
  const Bytes raw = test::gunzipFile(p);
  test::writeBytes(multi, test::multiMember(raw, {500, 1000, raw.size() / 2}));
  const Polylines again = io::readTrk(multi.string());
  EXPECT_EQ(again.offsets, lines.offsets);
  EXPECT_EQ(again.points, back.points);
}

TEST(GzipIo, TruncatedGzipFilesAreRefusedNamingTheFile) {
  const fs::path dir = test::scratchDir();
  const TensorField f = smallField();
  for (const char* name : kTensorNames) {
    const fs::path p = dir / name, cut = dir / (std::string("cut_") + name);
    io::writeTensorVolume(p.string(), f, io::TensorLayout::Fsl);
    Bytes b = test::readBytes(p);
    b.resize(b.size() * 2 / 3);
    test::writeBytes(cut, b);
    const std::string msg = inputError([&] { io::readTensorVolume(cut.string()); });
    EXPECT_NE(msg.find(cut.string()), std::string::npos) << name << ": " << msg;
    EXPECT_NE(msg.find("truncated"), std::string::npos) << name << ": " << msg;
  }
  Polylines lines;
  lines.points = {glm::vec3(1, 2, 3), glm::vec3(2, 3, 4), glm::vec3(3, 4, 5)};
  lines.offsets = {0, 3};
  const fs::path trk = dir / "t.trk.gz", cut = dir / "cut.trk.gz";
  io::writeTrk(trk.string(), lines, f.grid);
  Bytes b = test::readBytes(trk);
  b.resize(b.size() - 10); // the CRC-32 and size trailer lost
  test::writeBytes(cut, b);
  const std::string msg = inputError([&] { io::readTrk(cut.string()); });
  EXPECT_NE(msg.find(cut.string()), std::string::npos) << msg;
}

TEST(GzipIo, DeflateBombsAreRefusedBeforeInflatingThemWhole) {
  const fs::path dir = test::scratchDir();
  const TensorField f = smallField();
  // Each file's header declares a few KB; its stream inflates to 256 MiB of zeros from about 250 KB.
  const std::size_t extra = std::size_t(256) << 20;
  for (const char* name : {"t.nii.gz", "t.mif.gz"}) {
    const fs::path p = dir / name, b = dir / (std::string("bomb_") + name);
    io::writeTensorVolume(p.string(), f, io::TensorLayout::Fsl);
    test::writeBytes(b, test::bomb(test::gunzipFile(p), extra));
    ASSERT_LT(fs::file_size(b), extra / 500);
    const std::string msg = inputError([&] { io::readTensorVolume(b.string()); });
    EXPECT_NE(msg.find(b.string()), std::string::npos) << name << ": " << msg;
    EXPECT_NE(msg.find("deflate bomb"), std::string::npos) << name << ": " << msg;
  }
  const fs::path nrrd = dir / "t.nrrd", nb = dir / "bomb_t.nrrd";
  io::writeTensorVolume(nrrd.string(), f, io::TensorLayout::Fsl);
  const Bytes all = test::readBytes(nrrd);
  const std::string text(all.begin(), all.end());
  const std::size_t end = text.find("\n\n") + 2;
  Bytes out(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(end));
  test::writeBytes(dir / "data.gz", Bytes(all.begin() + static_cast<std::ptrdiff_t>(end), all.end()));
  const Bytes bombData = test::bomb(test::gunzipFile(dir / "data.gz"), extra);
  out.insert(out.end(), bombData.begin(), bombData.end());
  test::writeBytes(nb, out);
  const std::string msg = inputError([&] { io::readTensorVolume(nb.string()); });
  EXPECT_NE(msg.find(nb.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("deflate bomb"), std::string::npos) << msg;
}

TEST(GzipIo, AHeaderDeclaringGigabytesInATinyFileFailsWithoutAllocatingThem) {
  const fs::path dir = test::scratchDir();
  const fs::path p = dir / "t.nii.gz", huge = dir / "huge.nii.gz";
  io::writeTensorVolume(p.string(), smallField(), io::TensorLayout::Fsl);
  Bytes raw = test::gunzipFile(p);
  // dim[1..3] = 1200 x 1200 x 200, 6 float volumes: 6.9 GB declared, about 1 KB of data.
  const std::int16_t dims[3] = {1200, 1200, 200};
  std::memcpy(raw.data() + 42, dims, sizeof dims);
  test::writeBytes(huge, test::gzipMember(raw));
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = inputError([&] { io::readTensorVolume(huge.string()); });
  EXPECT_NE(msg.find(huge.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(GzipIo, InflaterReadsEveryMemberZlibDataAndRefusesPastItsLimit) {
  Bytes data(300000);
  for (std::size_t i = 0; i < data.size(); ++i)
    data[i] = static_cast<std::uint8_t>((i * 7919) % 251);
  const Bytes gz = test::multiMember(data, {1, 65536, 200000});
  const Bytes back = io::detail::inflateGzip("m.gz", gz.data(), gz.size(), 0, std::size_t(1) << 30);
  EXPECT_EQ(back, data);
  // A wrong size hint (too small, too large) changes nothing.
  EXPECT_EQ(io::detail::inflateGzip("m.gz", gz.data(), gz.size(), 10, std::size_t(1) << 30), data);
  EXPECT_EQ(io::detail::inflateGzip("m.gz", gz.data(), gz.size(), 1 << 22, std::size_t(1) << 30), data);
  // Trailing zeros after the last member (padding) are ignored.
  Bytes padded = gz;
  padded.resize(gz.size() + 512, 0);
  EXPECT_EQ(io::detail::inflateGzip("m.gz", padded.data(), padded.size(), 0, std::size_t(1) << 30), data);
  // zlib-wrapped data.
  uLongf zn = compressBound(static_cast<uLong>(data.size()));
  Bytes z(zn);
  ASSERT_EQ(compress(z.data(), &zn, data.data(), static_cast<uLong>(data.size())), Z_OK);
  z.resize(zn);
  EXPECT_EQ(io::detail::inflateGzip("z.bin", z.data(), z.size(), 0, std::size_t(1) << 30), data);
  // The limit: one byte less than the data.
  const std::string msg = inputError([&] { io::detail::inflateGzip("m.gz", gz.data(), gz.size(), 0, data.size() - 1); });
  EXPECT_NE(msg.find("m.gz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("deflate bomb"), std::string::npos) << msg;
  // A corrupted byte in the second member fails its check.
  Bytes bad = gz;
  bad[bad.size() / 2] ^= 0x55;
  EXPECT_NE(inputError([&] { io::detail::inflateGzip("m.gz", bad.data(), bad.size(), 0, std::size_t(1) << 30); }), "");
}
