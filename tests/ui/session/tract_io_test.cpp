// SPDX-License-Identifier: GPL-3.0-or-later
// Tract files: round trips through .tck, .trk (LAS and RAS reference grids) and .vtk, the TrackVis
// half-voxel convention in closed form, byte orders and datatypes, the real MRtrix/nibabel files against
// each other and the brain mask, and bad files refused with InputError naming the file.
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "support/test_env.h"
#include "surfaces/polyline_io.h"
#include "ui/session/tract_files.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace fs = std::filesystem;
using dtf::Grid;
using dtf::InputError;
using dtf::Polylines;

namespace {

// Three curved lines spanning about +-100 mm, plus a two-point line.
Polylines sampleLines() {
  Polylines l;
  l.offsets.push_back(0);
  for (int line = 0; line < 3; ++line) {
    for (int i = 0; i < 50 + 10 * line; ++i) {
      double t = i / 10.0;
      l.points.emplace_back(-90.0 + 3.7 * i + line, 40.0 * std::sin(t + line) - 20.0,
                            25.0 * std::cos(0.7 * t) + 10.0 * line);
    }
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  l.points.emplace_back(1.25f, -2.5f, 3.75f);
  l.points.emplace_back(2.25f, -3.5f, 4.75f);
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  return l;
}

// Largest point distance; fails when the line structure differs.
double maxDifference(const Polylines& a, const Polylines& b) {
  EXPECT_EQ(a.offsets, b.offsets);
  if (a.offsets != b.offsets || a.points.size() != b.points.size()) return 1e9;
  double m = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i)
    m = std::max(m, static_cast<double>(glm::length(a.points[i] - b.points[i])));
  return m;
}

// The real DWI grid: 72x72x39, 3 mm, LAS (sform of iu_prisma_dwi).
Grid lasGrid() {
  glm::dmat4 a(1.0);
  a[0][0] = -3;
  a[1][1] = 3;
  a[2][2] = 3;
  a[3] = glm::dvec4(108, -98.279, -23.396, 1);
  return Grid::fromAffine(glm::ivec3(72, 72, 39), a);
}
// An RAS grid with anisotropic voxels and an oblique (rotated) affine.
Grid rasObliqueGrid() {
  const double c = std::cos(0.2), s = std::sin(0.2);
  glm::dmat4 a(1.0);
  a[0] = glm::dvec4(2.0 * c, 2.0 * s, 0, 0);
  a[1] = glm::dvec4(-2.5 * s, 2.5 * c, 0, 0);
  a[2] = glm::dvec4(0, 0, 1.5, 0);
  a[3] = glm::dvec4(-100, -110, -60, 1);
  return Grid::fromAffine(glm::ivec3(100, 90, 80), a);
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const fs::path& p, const std::string& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
}
template <typename T> T leAt(const std::string& b, std::size_t off) {
  T v;
  std::memcpy(&v, b.data() + off, sizeof(T));
  return v; // the test machines are little-endian (checked below)
}
template <typename T> void putAt(std::string& b, std::size_t off, T v) {
  std::memcpy(b.data() + off, &v, sizeof(T));
}

// Expects InputError whose message names `file` and contains `what`.
template <typename Fn> void expectInputError(Fn fn, const fs::path& file, const std::string& what) {
  try {
    fn();
    ADD_FAILURE() << "no InputError for " << file << " (" << what << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

} // namespace

static_assert(std::endian::native == std::endian::little,
              "the byte-level checks below assume a little-endian host");

TEST(TractIo, TckRoundTripIsExactInFloat32) {
  auto dir = dtf::test::scratchDir();
  const Polylines lines = sampleLines();
  dtf::io::writeTck((dir / "a.tck").string(), lines);
  dtf::io::TckInfo info;
  Polylines back = dtf::io::readTck((dir / "a.tck").string(), &info);
  EXPECT_EQ(maxDifference(lines, back), 0.0);
  EXPECT_EQ(info.datatype, "Float32LE");
  EXPECT_EQ(info.declaredCount, 4);
  // Layout on disk: header, then points, a NaN triplet per line, an Inf triplet at the end.
  const std::string bytes = readBytes(dir / "a.tck");
  EXPECT_EQ(bytes.rfind("mrtrix tracks\n", 0), 0u);
  EXPECT_EQ(bytes.size(), info.dataOffset + 12 * (lines.points.size() + 4 + 1));
  EXPECT_TRUE(std::isinf(leAt<float>(bytes, bytes.size() - 4)));
  EXPECT_TRUE(std::isnan(leAt<float>(bytes, bytes.size() - 16)));
  EXPECT_FLOAT_EQ(leAt<float>(bytes, info.dataOffset), lines.points[0].x);
}

TEST(TractIo, TckBigEndianAndFloat64AreRead) {
  auto dir = dtf::test::scratchDir();
  const double pts[4][3] = {{1.5, -2.25, 3}, {4, 5.125, -6}, {7, 8, 9}, {-10, 11, 12.5}};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const char* type : {"Float64LE", "Float32BE", "Float64BE"}) {
    const bool be = std::string(type).find("BE") != std::string::npos, f64 = type[5] == '6';
    std::string head = std::string("mrtrix tracks\ndatatype: ") + type + "\ncount: 2\nfile: . 64\nEND\n";
    head.resize(64, ' ');
    std::string data = head;
    auto put = [&](double v) {
      char b[8];
      if (f64)
        std::memcpy(b, &v, 8);
      else {
        float f = static_cast<float>(v);
        std::memcpy(b, &f, 4);
      }
      const int n = f64 ? 8 : 4;
      if (be) std::reverse(b, b + n);
      data.append(b, static_cast<std::size_t>(n));
    };
    for (int i = 0; i < 4; ++i) {
      for (double v : pts[i])
        put(v);
      if (i == 1 || i == 3) put(nan), put(nan), put(nan);
    }
    put(inf), put(inf), put(inf);
    const fs::path p = dir / (std::string(type) + ".tck");
    writeBytes(p, data);
    Polylines l = dtf::io::readTck(p.string());
    ASSERT_EQ(l.lineCount(), 2u) << type;
    EXPECT_EQ(l.offsets[1], 2u);
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(l.points[static_cast<std::size_t>(i)][c], static_cast<float>(pts[i][c])) << type;
  }
}

TEST(TractIo, TrkRoundTripOnLasAndObliqueRasGrids) {
  auto dir = dtf::test::scratchDir();
  const Polylines lines = sampleLines();
  for (const Grid& g : {lasGrid(), rasObliqueGrid()}) {
    const fs::path p = dir / ("a_" + g.orientationCode() + ".trk");
    dtf::io::writeTrk(p.string(), lines, g);
    dtf::io::TrkInfo info;
    Polylines back = dtf::io::readTrk(p.string(), &info);
    EXPECT_LT(maxDifference(lines, back), 1e-4) << g.orientationCode();
    EXPECT_EQ(info.version, 2);
    EXPECT_EQ(info.dims, g.dims);
    EXPECT_EQ(info.voxelOrder, g.orientationCode());
    EXPECT_EQ(info.declaredCount, 4);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(info.voxelSize[a], g.spacing[a], 1e-6);
  }
  EXPECT_EQ(lasGrid().orientationCode(), "LAS");
  EXPECT_EQ(rasObliqueGrid().orientationCode(), "RAS");
}

// A point at the centre of voxel (i, j, k) is stored as ((i, j, k) + 0.5) * voxel size.
TEST(TractIo, TrkUsesTheHalfVoxelCornerConvention) {
  auto dir = dtf::test::scratchDir();
  const Grid g = lasGrid();
  Polylines l;
  l.offsets = {0, 2};
  l.points.emplace_back(g.toWorld(glm::dvec3(0, 0, 0)));
  l.points.emplace_back(g.toWorld(glm::dvec3(10, 20, 30)));
  dtf::io::writeTrk((dir / "c.trk").string(), l, g);
  const std::string b = readBytes(dir / "c.trk");
  ASSERT_EQ(b.size(), 1000u + 4 + 2 * 12);
  EXPECT_EQ(leAt<std::int32_t>(b, 1000), 2);
  EXPECT_NEAR(leAt<float>(b, 1004), 1.5f, 1e-5);
  EXPECT_NEAR(leAt<float>(b, 1008), 1.5f, 1e-5);
  EXPECT_NEAR(leAt<float>(b, 1012), 1.5f, 1e-5);
  EXPECT_NEAR(leAt<float>(b, 1016), 31.5f, 1e-4);
  EXPECT_NEAR(leAt<float>(b, 1020), 61.5f, 1e-4);
  EXPECT_NEAR(leAt<float>(b, 1024), 91.5f, 1e-4);
  EXPECT_EQ(b.substr(948, 3), "LAS");
  EXPECT_FLOAT_EQ(leAt<float>(b, 440), -3.0f);  // vox_to_ras[0][0]
  EXPECT_FLOAT_EQ(leAt<float>(b, 452), 108.0f); // vox_to_ras[0][3]
}

// v1 files (vox_to_ras all zero) are read as nibabel reads them: vox_to_ras is the identity (RAS), so a LAS
// voxel_order flips i within the 20 voxels: index (i, j, k) -> (19 - i, j, k). Big-endian files and unnamed
// per-point scalars / per-track properties are read too (as "scalars" / "properties").
TEST(TractIo, TrkV1BigEndianWithScalarsAndProperties) {
  auto dir = dtf::test::scratchDir();
  std::string h(1000, '\0');
  auto be16 = [](std::int16_t v) {
    return static_cast<std::int16_t>(__builtin_bswap16(static_cast<std::uint16_t>(v)));
  };
  auto be32 = [](std::int32_t v) {
    return static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(v)));
  };
  auto bef = [](float v) { return std::bit_cast<float>(__builtin_bswap32(std::bit_cast<std::uint32_t>(v))); };
  std::memcpy(h.data(), "TRACK", 5);
  for (int a = 0; a < 3; ++a) {
    putAt<std::int16_t>(h, 6 + 2 * a, be16(20));
    putAt<float>(h, 12 + 4 * a, bef(2.0f));
  }
  putAt<std::int16_t>(h, 36, be16(2));  // n_scalars
  putAt<std::int16_t>(h, 238, be16(1)); // n_properties
  std::memcpy(h.data() + 948, "LAS", 3);
  putAt<std::int32_t>(h, 988, be32(2));
  putAt<std::int32_t>(h, 992, be32(1));
  putAt<std::int32_t>(h, 996, be32(1000));
  std::string body = h;
  auto putF = [&](float v) {
    float b = bef(v);
    body.append(reinterpret_cast<const char*>(&b), 4);
  };
  auto putI = [&](std::int32_t v) {
    std::int32_t b = be32(v);
    body.append(reinterpret_cast<const char*>(&b), 4);
  };
  // Track 0: voxmm (1,1,1) and (5,3,1) -> index (0,0,0) and (2,1,0); track 1: one point voxmm (3,3,3).
  putI(2);
  putF(1), putF(1), putF(1), putF(99), putF(98);
  putF(5), putF(3), putF(1), putF(97), putF(96);
  putF(42); // property
  putI(1);
  putF(3), putF(3), putF(3), putF(0), putF(0);
  putF(43);
  writeBytes(dir / "v1.trk", body);
  dtf::io::TrkInfo info;
  Polylines l = dtf::io::readTrk((dir / "v1.trk").string(), &info);
  EXPECT_TRUE(info.bigEndian);
  EXPECT_EQ(info.version, 1);
  ASSERT_EQ(l.lineCount(), 2u);
  ASSERT_EQ(l.points.size(), 3u);
  EXPECT_NEAR(glm::length(l.points[0] - glm::vec3(19, 0, 0)), 0, 1e-6);
  EXPECT_NEAR(glm::length(l.points[1] - glm::vec3(17, 1, 0)), 0, 1e-6);
  EXPECT_NEAR(glm::length(l.points[2] - glm::vec3(18, 1, 1)), 0, 1e-6);
  ASSERT_EQ(l.perPoint.size(), 1u);
  EXPECT_EQ(l.perPoint[0].name, "scalars");
  EXPECT_EQ(l.perPoint[0].values, (std::vector<float>{99, 98, 97, 96, 0, 0}));
  ASSERT_EQ(l.perLine.size(), 1u);
  EXPECT_EQ(l.perLine[0].values, (std::vector<float>{42, 43}));
  // An unreadable voxel_order leaves the orientation unknown: refused.
  std::memcpy(body.data() + 948, "LQS", 3);
  writeBytes(dir / "v1bad.trk", body);
  expectInputError([&] { dtf::io::readTrk((dir / "v1bad.trk").string()); }, dir / "v1bad.trk", "voxel_order");
}

TEST(TractIo, VtkRoundTripAndDispatcher) {
  auto dir = dtf::test::scratchDir();
  const Polylines lines = sampleLines();
  dtf::surfaces::writeVtkPolylines((dir / "a.vtk").string(), lines);
  EXPECT_EQ(maxDifference(lines, dtf::surfaces::readVtkPolylines((dir / "a.vtk").string())), 0.0);
  const Grid g = lasGrid();
  for (const char* name : {"d.tck", "d.trk", "d.vtk"}) {
    const std::string p = (dir / name).string();
    dtf::session::writeTracts(p, lines, &g);
    EXPECT_LT(maxDifference(lines, dtf::session::readTracts(p)), 1e-4) << name;
  }
  EXPECT_THROW(dtf::session::writeTracts((dir / "e.trk").string(), lines, nullptr), dtf::UsageError);
  expectInputError([&] { dtf::session::readTracts((dir / "a.txt").string()); }, dir / "a.txt",
                   "unknown tract file extension");
}

TEST(TractIo, WritersAreAtomicAndRefuseNonFinitePoints) {
  auto dir = dtf::test::scratchDir();
  Polylines bad = sampleLines();
  bad.points[3].y = std::numeric_limits<float>::quiet_NaN();
  writeBytes(dir / "keep.tck", "old");
  EXPECT_THROW(dtf::io::writeTck((dir / "keep.tck").string(), bad), InputError);
  EXPECT_EQ(readBytes(dir / "keep.tck"), "old");
  EXPECT_THROW(dtf::io::writeTrk((dir / "b.trk").string(), bad, lasGrid()), InputError);
  EXPECT_THROW(dtf::surfaces::writeVtkPolylines((dir / "b.vtk").string(), bad), InputError);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos)
        << "temporary file left: " << e.path();
}

TEST(TractIo, BadFilesAreRefusedWithTheFileName) {
  auto dir = dtf::test::scratchDir();
  const Polylines lines = sampleLines();
  dtf::io::writeTck((dir / "good.tck").string(), lines);
  dtf::io::writeTrk((dir / "good.trk").string(), lines, lasGrid());
  const std::string tck = readBytes(dir / "good.tck"), trk = readBytes(dir / "good.trk");
  dtf::io::TckInfo info;
  dtf::io::readTck((dir / "good.tck").string(), &info);

  auto tckCase = [&](const std::string& name, const std::string& bytes, const std::string& what) {
    writeBytes(dir / name, bytes);
    expectInputError([&] { dtf::io::readTck((dir / name).string()); }, dir / name, what);
  };
  // Without the Inf triplet alone the data still ends after a NaN separator (read, with a warning); without
  // the last NaN too, the last streamline is truncated.
  tckCase("trunc1.tck", tck.substr(0, tck.size() - 24), "truncated");
  tckCase("trunc2.tck", tck.substr(0, tck.size() - 7), "truncated");
  tckCase("trunc3.tck", tck.substr(0, 30), "no END");
  tckCase("magic.tck", "mrtrix image\n" + tck.substr(14), "not an MRtrix .tck");
  std::string s = tck;
  s.replace(s.find("file: . ") + 8, 4, "9999");
  tckCase("offset.tck", s, "beyond the end");
  s = tck;
  s.replace(s.find("file: . ") + 8, 4, "10  ");
  tckCase("offset2.tck", s, "inside the header");
  // A count beyond the data is stale, not an error (tract_formats_test: StaleCountAndNaNEndedData).
  s = tck;
  s.replace(s.find("Float32LE"), 9, "Int16LE  ");
  tckCase("type.tck", s, "unsupported .tck datatype");
  s = tck;
  putAt<float>(s, info.dataOffset + 4, std::numeric_limits<float>::quiet_NaN());
  tckCase("nan.tck", s, "non-finite");
  expectInputError([&] { dtf::io::readTck((dir / "missing.tck").string()); }, dir / "missing.tck",
                   "no such file");

  auto trkCase = [&](const std::string& name, const std::string& bytes, const std::string& what) {
    writeBytes(dir / name, bytes);
    expectInputError([&] { dtf::io::readTrk((dir / name).string()); }, dir / name, what);
  };
  trkCase("short.trk", trk.substr(0, 500), "truncated TrackVis header");
  trkCase("trunc.trk", trk.substr(0, trk.size() - 5), "truncated TrackVis data");
  trkCase("trunc2.trk", trk.substr(0, 1000 + 4 + 12 * 50 + 2), "truncated TrackVis data");
  s = trk;
  s[0] = 'X';
  trkCase("magic.trk", s, "TRACK");
  s = trk;
  putAt<std::int32_t>(s, 996, 348);
  trkCase("hdr.trk", s, "header size");
  s = trk;
  putAt<std::int32_t>(s, 988, 2000000000);
  trkCase("count.trk", s, "impossible");
  s = trk;
  putAt<std::int32_t>(s, 1000, -5);
  trkCase("npoints.trk", s, "truncated TrackVis data");
  s = trk;
  putAt<float>(s, 1008, std::numeric_limits<float>::infinity());
  trkCase("inf.trk", s, "non-finite");
  s = trk;
  putAt<std::int32_t>(s, 992, 7);
  trkCase("version.trk", s, "version");

  writeBytes(dir / "bad.vtk",
             "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n1 2 3\n");
  expectInputError([&] { dtf::surfaces::readVtkPolylines((dir / "bad.vtk").string()); }, dir / "bad.vtk", "");
  writeBytes(dir / "notvtk.vtk", "hello\n");
  expectInputError([&] { dtf::surfaces::readVtkPolylines((dir / "notvtk.vtk").string()); },
                   dir / "notvtk.vtk", "not a legacy VTK");
}

// README: tracks_det.trk is tracks_det.tck converted by nibabel; a round trip differs by at most 7.6e-6 mm.
TEST(TractIoRealData, TckAndTrkAgreePointByPoint) {
  DTF_SHARED_FILE(tckPath, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(trkPath, "iu_prisma_dwi/derived/tracks_det.trk");
  Polylines tck = dtf::io::readTck(tckPath.string());
  dtf::io::TrkInfo info;
  Polylines trk = dtf::io::readTrk(trkPath.string(), &info);
  EXPECT_EQ(tck.lineCount(), 2000u);
  EXPECT_EQ(tck.points.size(), 147545u);
  EXPECT_EQ(info.voxelOrder, "LAS");
  EXPECT_EQ(info.dims, glm::ivec3(72, 72, 39));
  // float32 voxmm through a float32 affine: allow a few float ulps at ~100 mm beyond the README's figure.
  EXPECT_LT(maxDifference(tck, trk), 2e-5);
}

// tracks_det_first500.vtk is ASCII with 6 significant digits.
TEST(TractIoRealData, VtkHoldsTheFirst500TckStreamlines) {
  DTF_SHARED_FILE(tckPath, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(vtkPath, "iu_prisma_dwi/derived/tracks_det_first500.vtk");
  Polylines tck = dtf::io::readTck(tckPath.string());
  Polylines vtk = dtf::surfaces::readVtkPolylines(vtkPath.string());
  ASSERT_EQ(vtk.lineCount(), 500u);
  ASSERT_EQ(vtk.points.size(), 36700u);
  for (std::size_t l = 0; l <= 500; ++l)
    ASSERT_EQ(vtk.offsets[l], tck.offsets[l]);
  for (std::size_t i = 0; i < vtk.points.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(vtk.points[i][c], tck.points[i][c], 5e-6 * std::abs(tck.points[i][c]) + 1e-6)
          << "point " << i;
}

// Streamlines tracked inside mask.nii.gz stay in it: >= 95% of points in mask voxels dilated by one voxel.
TEST(TractIoRealData, RealTractsLandInsideTheBrainMask) {
  DTF_SHARED_FILE(tckPath, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(maskPath, "iu_prisma_dwi/derived/mask.nii.gz");
  const Polylines tck = dtf::io::readTck(tckPath.string());
  const dtf::ScalarVolume mask = dtf::io::readScalarVolume(maskPath.string());
  const Grid& g = mask.grid;
  std::vector<unsigned char> dilated(g.voxelCount(), 0);
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        if (mask.at(i, j, k) <= 0) continue;
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di)
              if (g.contains(i + di, j + dj, k + dk)) dilated[g.index(i + di, j + dj, k + dk)] = 1;
      }
  std::size_t inside = 0, strictlyInside = 0;
  for (const auto& p : tck.points) {
    glm::dvec3 v = g.toVoxel(glm::dvec3(p));
    int i = static_cast<int>(std::lround(v.x)), j = static_cast<int>(std::lround(v.y)),
        k = static_cast<int>(std::lround(v.z));
    if (!g.contains(i, j, k)) continue;
    inside += dilated[g.index(i, j, k)];
    strictlyInside += mask.at(i, j, k) > 0;
  }
  const double frac = static_cast<double>(inside) / static_cast<double>(tck.points.size());
  EXPECT_GE(frac, 0.95);
  // A wrong frame (e.g. ignoring the LAS flip) would put about half the points outside.
  EXPECT_GE(static_cast<double>(strictlyInside) / static_cast<double>(tck.points.size()), 0.9);
}

// Every truncation and a deterministic set of byte corruptions of small valid files: the readers either
// return finite points with consistent offsets or throw InputError, never anything else.
TEST(TractIo, CorruptedFilesNeverCrash) {
  auto dir = dtf::test::scratchDir();
  Polylines small;
  small.offsets = {0, 3, 5};
  small.points = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {-1, -2, -3}, {10, 20, 30}};
  dtf::io::writeTck((dir / "s.tck").string(), small);
  dtf::io::writeTrk((dir / "s.trk").string(), small, lasGrid());
  std::size_t refused = 0, read = 0;
  for (const char* name : {"s.tck", "s.trk"}) {
    const std::string good = readBytes(dir / name);
    const fs::path p = dir / (std::string("c_") + name);
    auto attempt = [&](const std::string& bytes) {
      writeBytes(p, bytes);
      try {
        Polylines l = dtf::session::readTracts(p.string());
        ASSERT_FALSE(l.offsets.empty());
        ASSERT_EQ(l.offsets.back(), l.points.size());
        for (const auto& q : l.points)
          ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z));
        ++read;
      } catch (const InputError&) {
        ++refused;
      }
    };
    for (std::size_t n = 0; n < good.size(); ++n)
      attempt(good.substr(0, n));
    std::uint32_t state = 12345;
    for (int k = 0; k < 1500; ++k) {
      state = state * 1664525u + 1013904223u;
      std::string b = good;
      const std::size_t at = (state >> 8) % b.size();
      b[at] = static_cast<char>(state >> 24);
      attempt(b);
    }
  }
  EXPECT_GT(refused, 0u);
  EXPECT_GT(read, 0u);
}
