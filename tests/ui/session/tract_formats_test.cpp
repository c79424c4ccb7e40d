// SPDX-License-Identifier: GPL-3.0-or-later
// Tractograms from every tool: each real file in ../shared/data/niivue_tracts against an independent reader
// (nibabel for TrackVis/MRtrix, Python's zipfile + numpy for TRX, a direct parse for legacy VTK), facts
// hard-coded from nibabel 5.0, the TrackVis LPS/no-affine rules, stale .tck counts and TRX offset and dtype
// variants built here byte by byte, round trips through every pair of formats, and bad TRX files refused.
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"
#include "io/formats/zip_archive.h"
#include "support/test_env.h"
#include "support/zip_builder.h"
#include "ui/session/tract_files.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>

namespace fs = std::filesystem;
using dtf::Grid;
using dtf::InputError;
using dtf::Polylines;
using dtf::TractValues;

namespace {

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const fs::path& p, const std::string& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
}
template <typename T> void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}
template <typename T> void poke(std::string& s, std::size_t at, T v) {
  std::memcpy(s.data() + at, &v, sizeof(T));
}
template <typename T> std::string arrayBytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename Fn> void expectInputError(Fn fn, const std::string& file, const std::string& what) {
  try {
    fn();
    ADD_FAILURE() << "no InputError for " << file << " (" << what << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

// A python3 that can import nibabel and numpy, or "" (then the reference tests fail under
// DTF_REQUIRE_SHARED_DATA, where .ci/setup installs python3-nibabel, and skip elsewhere).
std::string referencePython() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (std::system((std::string(py) + " -c 'import nibabel, numpy' >/dev/null 2>&1").c_str()) == 0)
      return py;
  return "";
}
#define DTF_REFERENCE_PYTHON(var)                                                                            \
  const std::string var = referencePython();                                                                 \
  if (var.empty()) {                                                                                         \
    if (dtf::test::envFlag("DTF_REQUIRE_SHARED_DATA"))                                                       \
      FAIL() << "python3 with nibabel and numpy is missing";                                                 \
    GTEST_SKIP() << "python3 with nibabel and numpy is missing";                                             \
  }

struct Reference {
  Polylines lines; // points, offsets and data as the independent reader gives them
};

// Runs tests/support/reference_tracts.py on `file`.
Reference independentRead(const std::string& python, const fs::path& file, const fs::path& scratch) {
  const fs::path out = scratch / ("ref_" + file.filename().string());
  const std::string cmd = python + " '" +
                          (dtf::test::sourceDir() / "tests/support/reference_tracts.py").string() + "' '" +
                          file.string() + "' '" + out.string() + "' 2>/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  Reference r;
  const std::string pts = readBytes(out.string() + ".points"), off = readBytes(out.string() + ".offsets");
  r.lines.points.resize(pts.size() / 12);
  std::memcpy(r.lines.points.data(), pts.data(), r.lines.points.size() * 12);
  for (std::size_t i = 0; i + 8 <= off.size(); i += 8) {
    std::int64_t v;
    std::memcpy(&v, off.data() + i, 8);
    r.lines.offsets.push_back(static_cast<std::uint32_t>(v));
  }
  std::ifstream names(out.string() + ".names");
  std::string kind;
  int index = 0, comps = 0;
  while (names >> kind >> index >> comps) {
    std::string name;
    std::getline(names, name);
    name = name.substr(1); // the space after the count; trailing spaces belong to the name
    const std::string raw = readBytes(out.string() + "." + kind + "." + std::to_string(index));
    TractValues v{name, comps, std::vector<float>(raw.size() / 4)};
    std::memcpy(v.values.data(), raw.data(), raw.size());
    (kind == "dps" ? r.lines.perLine : r.lines.perPoint).push_back(std::move(v));
  }
  return r;
}

// Same offsets; every coordinate within `tol` mm (plus `rel` of its magnitude).
void expectSameLines(const Polylines& got, const Polylines& want, double tol, double rel,
                     const std::string& what) {
  ASSERT_EQ(got.offsets, want.offsets) << what;
  ASSERT_EQ(got.points.size(), want.points.size()) << what;
  double worst = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < got.points.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::abs(double(got.points[i][c]) - double(want.points[i][c])) -
                       rel * std::abs(double(want.points[i][c]));
      if (d > worst) worst = d, at = i;
    }
  EXPECT_LE(worst, tol) << what << ": point " << at << " got (" << got.points[at].x << ", "
                        << got.points[at].y << ", " << got.points[at].z << "), want (" << want.points[at].x
                        << ", " << want.points[at].y << ", " << want.points[at].z << ")";
}

void expectSameData(const std::vector<TractValues>& got, const std::vector<TractValues>& want,
                    const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (const auto& w : want) {
    const TractValues* g = nullptr;
    for (const auto& x : got)
      if (x.name == w.name) g = &x;
    ASSERT_TRUE(g) << what << ": no data named '" << w.name << "'";
    EXPECT_EQ(g->components, w.components) << what << " " << w.name;
    ASSERT_EQ(g->values.size(), w.values.size()) << what << " " << w.name;
    for (std::size_t i = 0; i < w.values.size(); ++i)
      ASSERT_NEAR(g->values[i], w.values[i], 1e-6 * (1 + std::abs(w.values[i])))
          << what << " " << w.name << " [" << i << "]";
  }
}

// Collects warnings while alive.
struct WarningLog {
  std::vector<std::string> lines;
  WarningLog() {
    dtf::setLogSink([this](dtf::LogLevel level, const std::string& m) {
      if (level == dtf::LogLevel::Warning) lines.push_back(m);
    });
  }
  ~WarningLog() { dtf::setLogSink(nullptr); }
  bool has(const std::string& s) const {
    for (const auto& l : lines)
      if (l.find(s) != std::string::npos) return true;
    return false;
  }
};

// A TrackVis v2 header (little-endian): dims, voxel size, voxel_order, vox_to_ras (nullptr: all zero).
std::string trkHeader(glm::ivec3 dims, glm::vec3 vs, const char* order, const float* voxToRasRowMajor,
                      int count) {
  std::string h(1000, '\0');
  std::memcpy(h.data(), "TRACK", 5);
  for (int a = 0; a < 3; ++a) {
    poke<std::int16_t>(h, 6 + 2 * a, static_cast<std::int16_t>(dims[a]));
    poke<float>(h, 12 + 4 * a, vs[a]);
  }
  if (voxToRasRowMajor)
    for (int k = 0; k < 16; ++k)
      poke<float>(h, 440 + 4 * k, voxToRasRowMajor[k]);
  std::memcpy(h.data() + 948, order, std::strlen(order));
  poke<std::int32_t>(h, 988, count);
  poke<std::int32_t>(h, 992, 2);
  poke<std::int32_t>(h, 996, 1000);
  return h;
}

// Lines with two per-streamline arrays (1 and 3 components), one per-point array and two groups.
Polylines richLines() {
  Polylines l;
  l.offsets = {0};
  for (int line = 0; line < 5; ++line) {
    for (int i = 0; i < 10 + 3 * line; ++i)
      l.points.emplace_back(-60.0f + 4.5f * float(i), 30.0f * std::sin(0.3f * float(i) + float(line)) - 10.0f,
                            12.0f * float(line) - 20.0f + 0.37f * float(i));
    l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
  }
  TractValues w{"weight", 1, {}}, c{"colour", 3, {}}, fa{"fa", 1, {}};
  for (int line = 0; line < 5; ++line) {
    w.values.push_back(0.5f * float(line) + 0.25f);
    for (int k = 0; k < 3; ++k)
      c.values.push_back(float(line * 3 + k) / 16.0f);
  }
  for (std::size_t i = 0; i < l.points.size(); ++i)
    fa.values.push_back(float(i % 17) / 17.0f);
  l.perLine = {w, c};
  l.perPoint = {fa};
  l.groups = {{"left", {0, 2}}, {"right", {1, 3, 4}}};
  return l;
}

Grid lasReference() {
  glm::dmat4 a(1.0);
  a[0][0] = -2;
  a[1][1] = 2;
  a[2][2] = 2.5;
  a[3] = glm::dvec4(90, -126, -72, 1);
  return Grid::fromAffine(glm::ivec3(91, 109, 73), a);
}

} // namespace

// ---------------------------------------------------------------------------------------- real files

// Every file of the folder reads to the coordinates and data the independent reader gives. TrackVis goes
// through nibabel's float32 affine, so a few 1e-5 relative; TRX float16 positions are decoded the same way
// on both sides, so they agree to float32 rounding.
TEST(TractFormatsRealData, EveryFileMatchesAnIndependentReader) {
  DTF_SHARED_FILE(dir, "niivue_tracts");
  DTF_REFERENCE_PYTHON(python);
  const fs::path scratch = dtf::test::scratchDir();
  int compared = 0;
  for (const char* name : {"colby.trk", "colby.trx", "dpsv.trx", "afq_tractography.trx", "stroke.trk.gz",
                           "tract.IFOF_R.trk", "tract.SLF1_R.tck", "tract.FAT_R.vtk"}) {
    SCOPED_TRACE(name);
    const Polylines got = dtf::session::readTracts((dir / name).string());
    const Reference ref = independentRead(python, dir / name, scratch);
    expectSameLines(got, ref.lines, 1e-4, 2e-6, name);
    expectSameData(got.perLine, ref.lines.perLine, name);
    expectSameData(got.perPoint, ref.lines.perPoint, name);
    ++compared;
  }
  EXPECT_EQ(compared, 8);
}

// Facts as nibabel 5.0 and Python's zipfile report them for these files (see the data folder's README).
TEST(TractFormatsRealData, HeaderFactsCountsAndGroups) {
  DTF_SHARED_FILE(dir, "niivue_tracts");
  dtf::session::TractFileFacts f;
  Polylines colby = dtf::session::readTracts((dir / "colby.trk").string(), &f);
  ASSERT_EQ(colby.lineCount(), 2u);
  EXPECT_EQ(colby.points.size(), 32u);
  // nibabel: voxel_order LPS, vox_to_ras not recorded -> identity, flipped within 192x192x55.
  EXPECT_NEAR(colby.points[0].x, 191.5, 1e-4);
  EXPECT_NEAR(colby.points[0].y, -0.5, 1e-4);
  EXPECT_NEAR(colby.points[0].z, -0.5, 1e-4);
  EXPECT_NEAR(colby.points.back().x, 81.815475, 1e-4);
  EXPECT_NEAR(colby.points.back().y, 83.77749, 1e-4);
  EXPECT_NEAR(colby.points.back().z, 49.21125, 1e-4);
  // colby.trx, written independently, holds the same streamlines (float16: 1/16 mm steps above 128 mm).
  const Polylines colbyTrx = dtf::session::readTracts((dir / "colby.trx").string());
  for (std::size_t i = 0; i < colby.points.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(colbyTrx.points[i][c], colby.points[i][c], std::abs(colby.points[i][c]) / 1024 + 1e-3) << i;
  ASSERT_EQ(colbyTrx.perPoint.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_EQ(colbyTrx.perPoint[k].name, colby.perPoint[k].name);

  const Polylines stroke = dtf::session::readTracts((dir / "stroke.trk.gz").string(), &f);
  EXPECT_EQ(stroke.lineCount(), 36763u);
  EXPECT_EQ(stroke.points.size(), 237468u);
  EXPECT_NEAR(stroke.points[0].x, 63.796642, 1e-4);
  EXPECT_NEAR(stroke.points[0].y, -41.454803, 1e-4);
  EXPECT_NEAR(stroke.points[0].z, 2.3184967, 1e-4);
  EXPECT_NE(f.format.find("gzip"), std::string::npos) << f.format;
  ASSERT_TRUE(f.grid);
  EXPECT_EQ(f.grid->dims, glm::ivec3(181, 217, 181));
  EXPECT_EQ(f.grid->orientationCode(), "LAS");

  // dpsv.trx: header NB_STREAMLINES 459, but 460 offsets whose last (95708) is not NB_VERTICES (95865), a
  // jump between points 95707 and 95708 like every other streamline start, and 460 DataSetID values: 460
  // streamlines with a header count one short, read with a warning.
  WarningLog log;
  const Polylines dpsv = dtf::session::readTracts((dir / "dpsv.trx").string(), &f);
  EXPECT_EQ(dpsv.lineCount(), 460u);
  EXPECT_EQ(dpsv.offsets[459], 95708u);
  EXPECT_EQ(f.declaredCount, 459);
  EXPECT_TRUE(log.has("NB_STREAMLINES 459 but the offsets hold 460"));
  EXPECT_EQ(dpsv.points.size(), 95865u);
  ASSERT_EQ(dpsv.perLine.size(), 1u);
  EXPECT_EQ(dpsv.perLine[0].name, "DataSetID");
  ASSERT_EQ(dpsv.perPoint.size(), 1u);
  EXPECT_EQ(dpsv.perPoint[0].name, "z");
  ASSERT_TRUE(f.grid);
  EXPECT_NEAR(f.grid->spacing.x, 0.5, 1e-12);

  const Polylines afq = dtf::session::readTracts((dir / "afq_tractography.trx").string());
  EXPECT_EQ(afq.lineCount(), 508u);
  EXPECT_EQ(afq.points.size(), 141447u);
  ASSERT_EQ(afq.groups.size(), 2u);
  EXPECT_EQ(afq.groups[0].name, "ARC_L");
  EXPECT_EQ(afq.groups[0].lines.size(), 486u); // 1944 bytes of uint32
  EXPECT_EQ(afq.groups[1].name, "ARC_R");
  EXPECT_EQ(afq.groups[1].lines.size(), 22u);
  // pyAFQ's left arcuate lies left of the right one.
  double xl = 0, xr = 0;
  for (int g = 0; g < 2; ++g)
    for (std::uint32_t l : afq.groups[g].lines)
      (g ? xr : xl) += afq.points[afq.offsets[l]].x / double(afq.groups[g].lines.size());
  EXPECT_LT(xl, -10);
  EXPECT_GT(xr, 10);

  EXPECT_EQ(dtf::session::readTracts((dir / "tract.IFOF_R.trk").string()).lineCount(), 14u);
  EXPECT_EQ(dtf::session::readTracts((dir / "tract.SLF1_R.tck").string()).lineCount(), 13u);
  EXPECT_EQ(dtf::session::readTracts((dir / "tract.FAT_R.vtk").string()).lineCount(), 5u);
}

// issue1298.vtk is legacy VTK 5.1 (OFFSETS/CONNECTIVITY); VTK 9.1's reader reads it, and it holds 500
// triangles and no lines: a surface mesh, refused as tracts with what it holds.
TEST(TractFormatsRealData, Vtk51FileIsReadByVtkAndHoldsASurface) {
  DTF_SHARED_FILE(file, "niivue_tracts/issue1298.vtk");
  expectInputError([&] { dtf::session::readTracts(file.string()); }, file.string(),
                   "260 points, 500 polygons");
}

// ---------------------------------------------------------------------------------------- TrackVis rules

// voxel_order LPS with no vox_to_ras (nibabel: identity, flip x and y within the dims); voxel_order LPS with
// an RAS vox_to_ras (flip, then the affine); no voxel_order (LPS assumed); LAS with a LAS affine (no flip).
// Closed-form expectations, and nibabel's reading of the same bytes when it is available.
TEST(TractFormatsTrk, LpsAndNoAffineRulesAsNibabel) {
  const fs::path dir = dtf::test::scratchDir();
  std::string body;
  put<std::int32_t>(body, 2);
  for (float v : {0.0f, 0.0f, 0.0f, 5.0f, 7.0f, 9.0f})
    put<float>(body, v);
  const float rasAffine[16] = {2, 0, 0, -10, 0, 2, 0, -20, 0, 0, 3, -30, 0, 0, 0, 1};
  const float lasAffine[16] = {-2, 0, 0, 10, 0, 2, 0, -20, 0, 0, 3, -30, 0, 0, 0, 1};
  struct Case {
    const char* file;
    std::string bytes;
    glm::vec3 first, second;
    const char* warning;
  };
  const glm::ivec3 dims(10, 20, 30);
  const glm::vec3 vs(2, 2, 3);
  // voxmm (0,0,0) -> index (-0.5,-0.5,-0.5); (5,7,9) -> (2,3,2.5). LPS->RAS flips x, y: i' = dims - 1 - i.
  std::vector<Case> cases = {
      {"lps_noaffine.trk",
       trkHeader(dims, vs, "LPS", nullptr, 1) + body,
       {9.5f, 19.5f, -0.5f},
       {7, 16, 2.5f},
       "no vox_to_ras"},
      {"lps_ras.trk",
       trkHeader(dims, vs, "LPS", rasAffine, 1) + body,
       {2 * 9.5f - 10, 2 * 19.5f - 20, 3 * -0.5f - 30},
       {2 * 7 - 10, 2 * 16 - 20, 3 * 2.5f - 30},
       nullptr},
      {"noorder_noaffine.trk",
       trkHeader(dims, vs, "", nullptr, 1) + body,
       {9.5f, 19.5f, -0.5f},
       {7, 16, 2.5f},
       "no voxel_order"},
      {"las_las.trk",
       trkHeader(dims, vs, "LAS", lasAffine, 1) + body,
       {-2 * -0.5f + 10, 2 * -0.5f - 20, 3 * -0.5f - 30},
       {-2 * 2 + 10, 2 * 3 - 20, 3 * 2.5f - 30},
       nullptr},
      {"ras_noaffine.trk.gz", "", {-0.5f, -0.5f, -0.5f}, {2, 3, 2.5f}, "no vox_to_ras"},
  };
  {
    // Gzip the RAS/no-affine case through the writer's own compression path would prove nothing; use zlib.
    const std::string raw = trkHeader(dims, vs, "RAS", nullptr, 1) + body;
    z_stream z{};
    deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    std::string gz(deflateBound(&z, static_cast<uLong>(raw.size())) + 32, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
    z.avail_in = static_cast<uInt>(raw.size());
    z.next_out = reinterpret_cast<Bytef*>(gz.data());
    z.avail_out = static_cast<uInt>(gz.size());
    deflate(&z, Z_FINISH);
    gz.resize(z.total_out);
    deflateEnd(&z);
    cases.back().bytes = gz;
  }
  const std::string python = referencePython();
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    writeBytes(dir / c.file, c.bytes);
    WarningLog log;
    const Polylines l = dtf::session::readTracts((dir / c.file).string());
    ASSERT_EQ(l.points.size(), 2u);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(l.points[0][k], c.first[k], 1e-5);
      EXPECT_NEAR(l.points[1][k], c.second[k], 1e-5);
    }
    if (c.warning) {
      EXPECT_TRUE(log.has(c.warning)) << c.warning;
    }
    if (!python.empty()) {
      const Reference ref = independentRead(python, dir / c.file, dir);
      expectSameLines(l, ref.lines, 1e-5, 0, c.file);
    }
  }
  if (python.empty() && dtf::test::envFlag("DTF_REQUIRE_SHARED_DATA"))
    FAIL() << "python3 with nibabel is missing";
}

// Scalars and properties become per-point and per-streamline data named from the header; a name with a
// count after its NUL holds that many values; unnamed values are called "scalars"/"properties".
TEST(TractFormatsTrk, ScalarsAndPropertiesBecomeData) {
  const fs::path dir = dtf::test::scratchDir();
  const float ras[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::string h = trkHeader({10, 10, 10}, {1, 1, 1}, "RAS", ras, 1);
  poke<std::int16_t>(h, 36, 4); // 4 scalars: "rgb" x3, then one unnamed
  std::memcpy(h.data() + 38, "rgb\0003", 5);
  poke<std::int16_t>(h, 238, 1); // 1 property "len"
  std::memcpy(h.data() + 240, "len", 3);
  std::string body;
  put<std::int32_t>(body, 2);
  for (float v : {1.f, 2.f, 3.f, 0.1f, 0.2f, 0.3f, 9.f, 4.f, 5.f, 6.f, 0.4f, 0.5f, 0.6f, 8.f, 42.f})
    put<float>(body, v);
  writeBytes(dir / "s.trk", h + body);
  const Polylines l = dtf::io::readTrk((dir / "s.trk").string());
  ASSERT_EQ(l.perPoint.size(), 2u);
  EXPECT_EQ(l.perPoint[0].name, "rgb");
  EXPECT_EQ(l.perPoint[0].components, 3);
  EXPECT_EQ(l.perPoint[0].values, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}));
  EXPECT_EQ(l.perPoint[1].name, "scalars");
  EXPECT_EQ(l.perPoint[1].values, (std::vector<float>{9, 8}));
  ASSERT_EQ(l.perLine.size(), 1u);
  EXPECT_EQ(l.perLine[0].name, "len");
  EXPECT_EQ(l.perLine[0].values, (std::vector<float>{42}));
  EXPECT_NEAR(l.points[1].x, 3.5, 1e-6); // voxmm 4 -> index 3.5 -> identity
}

// ---------------------------------------------------------------------------------------- .tck

// A MATLAB-style file: count 5 for 2 streamlines, the data ending with a NaN triplet and no Inf. Read to
// the end with warnings (as nibabel reads it); a partial triplet or an unterminated streamline stays an
// error.
TEST(TractFormatsTck, StaleCountAndNaNEndedData) {
  const fs::path dir = dtf::test::scratchDir();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto tck = [](const std::string& count, const std::vector<float>& pts) {
    std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: " + count + "\nfile: . 0000000000\nEND\n";
    char off[16];
    std::snprintf(off, sizeof off, "%010zu", head.size());
    head.replace(head.find("0000000000"), 10, off);
    std::string b = head;
    for (float v : pts)
      put<float>(b, v);
    return b;
  };
  const float inf = std::numeric_limits<float>::infinity();
  // Stale count, data ended by Inf: nibabel 5.0 reads it (ignoring the count).
  writeBytes(dir / "stale.tck",
             tck("5", {1, 2, 3, 4, 5, 6, nan, nan, nan, 7, 8, 9, nan, nan, nan, inf, inf, inf}));
  {
    WarningLog log;
    const Polylines l = dtf::session::readTracts((dir / "stale.tck").string());
    EXPECT_EQ(l.offsets, (std::vector<std::uint32_t>{0, 2, 3}));
    EXPECT_TRUE(log.has("header count 5 but 2 streamlines"));
    if (const std::string python = referencePython(); !python.empty())
      expectSameLines(l, independentRead(python, dir / "stale.tck", dir).lines, 0, 0, "stale.tck");
  }
  // The same data ending with the NaN triplet and no Inf (MATLAB writers). nibabel 5.0 refuses it
  // ("Expecting end-of-file marker"); it is read here to the end of the data, with a warning.
  writeBytes(dir / "nanend.tck", tck("5", {1, 2, 3, 4, 5, 6, nan, nan, nan, 7, 8, 9, nan, nan, nan}));
  WarningLog log;
  const Polylines l = dtf::session::readTracts((dir / "nanend.tck").string());
  EXPECT_EQ(l.lineCount(), 2u);
  EXPECT_EQ(l.offsets, (std::vector<std::uint32_t>{0, 2, 3}));
  EXPECT_EQ(l.points[0], glm::vec3(1, 2, 3));
  EXPECT_EQ(l.points[2], glm::vec3(7, 8, 9));
  EXPECT_TRUE(log.has("header count 5 but 2 streamlines"));
  EXPECT_TRUE(log.has("no Inf end marker"));
  writeBytes(dir / "open.tck", tck("1", {1, 2, 3, 4, 5, 6}));
  expectInputError([&] { dtf::session::readTracts((dir / "open.tck").string()); }, "open.tck",
                   "no NaN separator");
  std::string cut = tck("1", {1, 2, 3, nan, nan, nan});
  writeBytes(dir / "cut.tck", cut.substr(0, cut.size() - 2));
  expectInputError([&] { dtf::session::readTracts((dir / "cut.tck").string()); }, "cut.tck",
                   "ends inside a triplet");
}

// ---------------------------------------------------------------------------------------- TRX

namespace {
std::uint16_t toHalf(float f) { // exact for the values used here (small integers and halves)
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  const std::uint32_t sign = (b >> 16) & 0x8000u;
  const int exp = int((b >> 23) & 0xff) - 127 + 15;
  if ((b & 0x7fffffffu) == 0) return static_cast<std::uint16_t>(sign);
  return static_cast<std::uint16_t>(sign | (std::uint32_t(exp) << 10) | ((b >> 13) & 0x3ffu));
}

struct TrxParts {
  std::vector<dtf::test::ZipEntry> entries;
};

// Three streamlines (2, 3, 1 points) at small exact coordinates, with the chosen dtypes.
std::vector<dtf::test::ZipEntry> trxEntries(const std::string& posType, const std::string& offType,
                                            bool withEnd, bool deflate) {
  const std::vector<float> p = {0, 1, 2, 3, 4, 5, -1.5f, 2.5f, 8, 10, 11, 12, 13, 14, 15, 100, -50, 25.5f};
  std::string pos;
  for (float v : p) {
    if (posType == "float16") put<std::uint16_t>(pos, toHalf(v));
    if (posType == "float32") put<float>(pos, v);
    if (posType == "float64") put<double>(pos, v);
  }
  std::vector<std::uint64_t> off = {0, 2, 5};
  if (withEnd) off.push_back(6);
  std::string offs;
  for (auto o : off)
    offType == "uint32" ? put<std::uint32_t>(offs, std::uint32_t(o)) : put<std::uint64_t>(offs, o);
  const std::string header =
      R"({"VOXEL_TO_RASMM": [[2, 0, 0, -10], [0, 2, 0, -20], [0, 0, 2, -30], [0, 0, 0, 1]],
    "DIMENSIONS": [10, 20, 30], "NB_STREAMLINES": 3, "NB_VERTICES": 6})";
  std::string dps, dpv, grp;
  for (float v : {1.f, 2.f, 3.f})
    put<float>(dps, v);
  for (int i = 0; i < 6; ++i)
    put<std::int16_t>(dpv, static_cast<std::int16_t>(i * 10));
  for (std::uint32_t g : {2u, 0u})
    put<std::uint32_t>(grp, g);
  return {{"header.json", header, deflate},      {"positions.3." + posType, pos, deflate},
          {"offsets." + offType, offs, deflate}, {"dps/", "", false},
          {"dps/score.float32", dps, deflate},   {"dpv/depth.int16", dpv, deflate},
          {"groups/pair.uint32", grp, deflate}};
}
} // namespace

// float16/32/64 positions x uint32/uint64 offsets x with/without the end entry x stored/deflated/folder:
// all read to the same streamlines, data and groups.
TEST(TractFormatsTrx, DtypeAndOffsetVariantsReadAlike) {
  const fs::path dir = dtf::test::scratchDir();
  int n = 0;
  for (const char* pos : {"float16", "float32", "float64"})
    for (const char* off : {"uint32", "uint64"})
      for (bool end : {false, true})
        for (int form = 0; form < 3; ++form) {
          const std::string name =
              std::string("v_") + pos + "_" + off + (end ? "_end" : "") + "_" + std::to_string(form) + ".trx";
          SCOPED_TRACE(name);
          const auto entries = trxEntries(pos, off, end, form == 1);
          if (form == 2) {
            fs::create_directories(dir / name);
            for (const auto& e : entries) {
              if (e.name.back() == '/') continue;
              fs::create_directories((dir / name / e.name).parent_path());
              writeBytes(dir / name / e.name, e.data);
            }
          } else {
            writeBytes(dir / name, dtf::test::zipArchive(entries));
          }
          dtf::io::TrxInfo info;
          const Polylines l = dtf::io::readTrx((dir / name).string(), &info);
          EXPECT_EQ(info.folder, form == 2);
          EXPECT_EQ(info.offsetsHaveEnd, end);
          EXPECT_EQ(info.deflatedEntries, form == 1 ? 6 : 0);
          EXPECT_EQ(info.positionsDtype, pos);
          ASSERT_EQ(l.offsets, (std::vector<std::uint32_t>{0, 2, 5, 6}));
          EXPECT_EQ(l.points[2], glm::vec3(-1.5f, 2.5f, 8)); // positions are RAS mm as stored
          EXPECT_EQ(l.points[5], glm::vec3(100, -50, 25.5f));
          ASSERT_EQ(l.perLine.size(), 1u);
          EXPECT_EQ(l.perLine[0].name, "score");
          EXPECT_EQ(l.perLine[0].values, (std::vector<float>{1, 2, 3}));
          ASSERT_EQ(l.perPoint.size(), 1u);
          EXPECT_EQ(l.perPoint[0].values, (std::vector<float>{0, 10, 20, 30, 40, 50}));
          ASSERT_EQ(l.groups.size(), 1u);
          EXPECT_EQ(l.groups[0].lines, (std::vector<std::uint32_t>{2, 0}));
          EXPECT_EQ(info.voxToRas[3][0], -10);
          ++n;
        }
  EXPECT_EQ(n, 36);
}

// header.json as other writers may lay it out: any valid JSON reads the same (escaped key names, exponents,
// whitespace of every kind, members in any order, unknown members of every type, deep nesting).
TEST(TractFormatsTrx, UnusualButValidHeadersReadAlike) {
  const fs::path dir = dtf::test::scratchDir();
  const std::vector<std::pair<std::string, std::string>> headers = {
      {"whitespace.trx",
       "\r\n\t {\r\n\t\"NB_VERTICES\"\t:\r\n6 ,\n\"NB_STREAMLINES\" :3,\"DIMENSIONS\":[ 10 ,20,\t30 ] ,"
       "\"VOXEL_TO_RASMM\":[[2,0,0,-10],[0,2,0,-20],[0,0,2,-30],[0,0,0,1]]\n}\n\t "},
      {"exponents.trx",
       R"({"NB_STREAMLINES": 3e0, "NB_VERTICES": 0.6E1, "DIMENSIONS": [1e1, 2.0e+1, 300e-1],
           "VOXEL_TO_RASMM": [[2E0, 0.0, -0e0, -1.0e1], [0, 20e-1, 0, -2e+1], [0, 0, 2.000, -30.0e0],
                              [0, 0, 0, 1e0]]})"},
      {"escapes.trx",
       R"({"NB_\u0053TREAMLINES": 3, "\u004eB_VERTICES": 6, "DIMENSIONS": [10, 20, 30],
           "VOXEL_TO_RASMM": [[2, 0, 0, -10], [0, 2, 0, -20], [0, 0, 2, -30], [0, 0, 0, 1]],
           "COMMENT": "a \"quoted\" \\ back\/slash, tab\t, caf\u00e9, \ud83e\udde0, caf\u00c3\u00a9 as bytes"})"},
      {"order_and_extras.trx",
       R"({"extra": {"nested": {"list": [1, -2.5e-3, "s", true, false, null, [], {}]}}, "flag": false,
           "VOXEL_TO_RASMM": [[2, 0, 0, -10], [0, 2, 0, -20], [0, 0, 2, -30], [0, 0, 0, 1]], "nothing": null,
           "DIMENSIONS": [10, 20, 30], "NB_VERTICES": 6, "NB_STREAMLINES": 3, "NB_GROUPS": 1})"},
      {"deep.trx", "{\"deep\": " + std::string(5000, '[') + std::string(5000, ']') +
                       R"(, "NB_STREAMLINES": 3, "NB_VERTICES": 6, "DIMENSIONS": [10, 20, 30],
           "VOXEL_TO_RASMM": [[2, 0, 0, -10], [0, 2, 0, -20], [0, 0, 2, -30], [0, 0, 0, 1]]})"},
  };
  for (const auto& [name, header] : headers) {
    SCOPED_TRACE(name);
    auto entries = trxEntries("float32", "uint32", true, false);
    entries[0].data = header;
    writeBytes(dir / name, dtf::test::zipArchive(entries));
    dtf::io::TrxInfo info;
    const Polylines l = dtf::io::readTrx((dir / name).string(), &info);
    EXPECT_EQ(info.nbStreamlines, 3);
    EXPECT_EQ(info.nbVertices, 6);
    EXPECT_EQ(info.dims[0], 10);
    EXPECT_EQ(info.dims[1], 20);
    EXPECT_EQ(info.dims[2], 30);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        EXPECT_EQ(info.voxToRas[c][r], r == c ? (r < 3 ? 2 : 1) : c == 3 ? -10.0 * (r + 1) : 0) << r << c;
    ASSERT_EQ(l.offsets, (std::vector<std::uint32_t>{0, 2, 5, 6}));
    EXPECT_EQ(l.points[5], glm::vec3(100, -50, 25.5f));
  }
}

// Headers that are not valid JSON, or valid JSON without what a TRX header needs.
TEST(TractFormatsTrx, MalformedHeadersAreRefused) {
  const fs::path dir = dtf::test::scratchDir();
  const std::string affine = R"("VOXEL_TO_RASMM": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]])";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"trailing.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6} x)", "bad TRX header.json: not valid JSON"},
      {"comma.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6,})", "bad TRX header.json: not valid JSON"},
      {"single.trx", R"({'NB_STREAMLINES': 3, 'NB_VERTICES': 6})", "bad TRX header.json: not valid JSON"},
      {"nan.trx", R"({"NB_STREAMLINES": NaN, "NB_VERTICES": 6})", "bad TRX header.json: not valid JSON"},
      {"overflow.trx", R"({"NB_STREAMLINES": 1e999, "NB_VERTICES": 6})", "bad TRX header.json: not valid JSON"},
      {"utf8.trx", "{\"NB_STREAMLINES\": 3, \"NB_VERTICES\": 6, \"x\": \"\xff\xfe\"}",
       "bad TRX header.json: not valid JSON"},
      {"control.trx", "{\"NB_STREAMLINES\": 3, \"NB_VERTICES\": 6, \"x\": \"a\nb\"}",
       "bad TRX header.json: not valid JSON"},
      {"empty.trx", "", "bad TRX header.json: not valid JSON"},
      {"array.trx", "[3, 6]", "TRX header.json is not a JSON object"},
      {"string.trx", R"({"NB_STREAMLINES": "3", "NB_VERTICES": 6})", "no valid NB_STREAMLINES"},
      {"fraction.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6.5})", "no valid NB_VERTICES"},
      {"negative.trx", R"({"NB_STREAMLINES": -3, "NB_VERTICES": 6})", "no valid NB_STREAMLINES"},
      {"huge.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 1e12})", "no valid NB_VERTICES"},
      {"missing.trx", R"({"NB_VERTICES": 6})", "no valid NB_STREAMLINES"},
      {"affine.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6, "VOXEL_TO_RASMM": [[1,0,0],[0,1,0],[0,0,1]]})",
       "VOXEL_TO_RASMM is not a 4x4 array of numbers"},
      {"affinetext.trx",
       R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6, "VOXEL_TO_RASMM": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,"1"]]})",
       "VOXEL_TO_RASMM is not a 4x4 array of numbers"},
      {"dims.trx", R"({"NB_STREAMLINES": 3, "NB_VERTICES": 6, )" + affine + R"(, "DIMENSIONS": [10, 20.5, 30]})",
       "DIMENSIONS is not three non-negative integers"},
  };
  for (const auto& [name, header, why] : cases) {
    SCOPED_TRACE(name);
    auto entries = trxEntries("float32", "uint32", true, false);
    entries[0].data = header;
    writeBytes(dir / name, dtf::test::zipArchive(entries));
    expectInputError([&] { dtf::session::readTracts((dir / name).string()); }, name, why);
  }
}

// Bad TRX files: each refused with the file name and the reason.
TEST(TractFormatsTrx, BadFilesAreRefused) {
  const fs::path dir = dtf::test::scratchDir();
  auto good = [] { return trxEntries("float32", "uint32", true, false); };
  auto with = [&](const std::function<void(std::vector<dtf::test::ZipEntry>&)>& edit) {
    auto e = good();
    edit(e);
    return dtf::test::zipArchive(e);
  };
  auto find = [](std::vector<dtf::test::ZipEntry>& e, const std::string& prefix) -> dtf::test::ZipEntry& {
    for (auto& x : e)
      if (x.name.rfind(prefix, 0) == 0) return x;
    throw std::runtime_error(prefix);
  };
  const std::string zip = dtf::test::zipArchive(good());
  struct Bad {
    const char* file;
    std::string bytes;
    const char* why;
  };
  std::string badCrc = zip;
  badCrc[45] ^= 0x55; // inside header.json's stored bytes (30-byte local header + 11-byte name)
  const std::vector<Bad> cases = {
      {"notzip.trx", "this is not a zip archive at all, not even close",
       "no end-of-central-directory record"},
      {"truncated.trx", zip.substr(0, zip.size() / 2), "no end-of-central-directory record"},
      {"crc.trx", badCrc, "CRC-32"},
      {"noheader.trx", with([](auto& e) { e.erase(e.begin()); }), "no header.json"},
      {"badjson.trx", with([&](auto& e) { find(e, "header.json").data = "{\"NB_STREAMLINES\": 3,"; }),
       "bad TRX header.json"},
      {"offsets.trx", with([&](auto& e) { poke<std::uint32_t>(find(e, "offsets.").data, 4, 7); }),
       "offsets are inconsistent"},
      {"offsetend.trx", with([&](auto& e) { poke<std::uint32_t>(find(e, "offsets.").data, 12, 7); }),
       "offsets are inconsistent at entry 3"},
      {"stalecount.trx", with([&](auto& e) { poke<std::uint32_t>(find(e, "offsets.").data, 12, 5); }),
       "'dps/score.float32' holds 12 bytes, expected 16"},
      {"possize.trx", with([&](auto& e) { find(e, "positions.").data.resize(60); }),
       "NB_VERTICES 6 needs 72"},
      {"offsize.trx", with([&](auto& e) { find(e, "offsets.").data.resize(8); }), "NB_STREAMLINES 3 needs"},
      {"dtype.trx", with([&](auto& e) { find(e, "positions.").name = "positions.3.float128"; }),
       "positions.3.float16|float32|float64"},
      {"offdtype.trx", with([&](auto& e) { find(e, "offsets.").name = "offsets.int32"; }), "unknown dtype"},
      {"dpsdtype.trx", with([&](auto& e) { find(e, "dps/score").name = "dps/score.complex64"; }),
       "unknown dtype 'complex64'"},
      {"dpssize.trx", with([&](auto& e) { find(e, "dps/score").data.resize(8); }), "expected 12"},
      {"group.trx", with([&](auto& e) { poke<std::uint32_t>(find(e, "groups/").data, 0, 3); }),
       "names streamline 3 of 3"},
      {"escape.trx", with([](auto& e) {
         e.push_back({"../../evil.float32", "abcd", false});
       }),
       "escapes the archive"},
      {"absolute.trx", with([](auto& e) {
         e.push_back({"/etc/evil", "abcd", false});
       }),
       "escapes the archive"},
      {"nan.trx", with([&](auto& e) { poke<float>(find(e, "positions.").data, 4, std::nanf("")); }),
       "position 0 is not finite"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    writeBytes(dir / c.file, c.bytes);
    expectInputError([&] { dtf::session::readTracts((dir / c.file).string()); }, c.file, c.why);
  }
  // A folder whose entry is a symbolic link out of it.
  fs::create_directories(dir / "linked.trx");
  for (const auto& e : good())
    if (e.name.back() != '/') {
      fs::create_directories((dir / "linked.trx" / e.name).parent_path());
      writeBytes(dir / "linked.trx" / e.name, e.data);
    }
  fs::create_symlink("/etc/hostname", dir / "linked.trx" / "dpv" / "x.float32");
  expectInputError([&] { dtf::session::readTracts((dir / "linked.trx").string()); }, "linked.trx",
                   "symbolic link");
}

// ---------------------------------------------------------------------------------------- round trips

// Every ordered pair of formats: A -> B keeps coordinates (float32) and the data both ends hold: .trk
// per-point (scalars) and per-streamline (properties), .vtk/.vtp both, .trx both and groups, .tck none.
TEST(TractFormatsRoundTrip, EveryPairKeepsCoordinatesAndSharedData) {
  const fs::path dir = dtf::test::scratchDir();
  const Polylines src = richLines();
  const Grid ref = lasReference();
  struct Fmt {
    const char* ext;
    bool data, groups;
  };
  const std::vector<Fmt> fmts = {{".tck", false, false}, {".trk", true, false}, {".trk.gz", true, false},
                                 {".trx", true, true},   {".vtk", true, false}, {".vtp", true, false}};
  int pairs = 0;
  for (const auto& a : fmts)
    for (const auto& b : fmts) {
      const std::string pa = (dir / (std::string("a") + std::to_string(pairs) + a.ext)).string();
      const std::string pb = (dir / (std::string("b") + std::to_string(pairs) + b.ext)).string();
      SCOPED_TRACE(std::string(a.ext) + " -> " + b.ext);
      WarningLog log;
      dtf::session::writeTracts(pa, src, &ref);
      const Polylines mid = dtf::session::readTracts(pa);
      dtf::session::writeTracts(pb, mid, &ref);
      const Polylines end = dtf::session::readTracts(pb);
      expectSameLines(end, src, 2e-5, 2e-6, pb);
      const bool data = a.data && b.data, groups = a.groups && b.groups;
      if (data) {
        expectSameData(end.perLine, src.perLine, pb);
        expectSameData(end.perPoint, src.perPoint, pb);
      } else {
        EXPECT_TRUE(end.perLine.empty() && end.perPoint.empty());
        EXPECT_TRUE(log.has("dropped")) << "no warning about dropped data";
      }
      if (groups) {
        ASSERT_EQ(end.groups.size(), 2u);
        EXPECT_EQ(end.groups[0].name, "left");
        EXPECT_EQ(end.groups[1].lines, (std::vector<std::uint32_t>{1, 3, 4}));
      } else {
        EXPECT_TRUE(end.groups.empty());
        EXPECT_TRUE(log.has("groups; dropped")) << "no warning about dropped groups";
      }
      ++pairs;
    }
  EXPECT_EQ(pairs, 36);
}

// The TRX writer's zip is read by Python's zipfile, and its header by json (an independent reader).
TEST(TractFormatsRoundTrip, WrittenTrxReadsInPython) {
  DTF_REFERENCE_PYTHON(python);
  const fs::path dir = dtf::test::scratchDir();
  const Polylines src = richLines();
  const Grid ref = lasReference();
  dtf::io::writeTrx((dir / "w.trx").string(), src, ref);
  const Reference r = independentRead(python, dir / "w.trx", dir);
  expectSameLines(src, r.lines, 0, 0, "w.trx");
  expectSameData(src.perLine, r.lines.perLine, "w.trx");
  expectSameData(src.perPoint, r.lines.perPoint, "w.trx");
  // And a TrackVis file written here reads in nibabel to the same coordinates.
  dtf::io::writeTrk((dir / "w.trk.gz").string(), src, ref);
  const Reference t = independentRead(python, dir / "w.trk.gz", dir);
  expectSameLines(t.lines, src, 2e-5, 2e-6, "w.trk.gz");
  expectSameData(t.lines.perPoint, src.perPoint, "w.trk.gz");
  expectSameData(t.lines.perLine, src.perLine, "w.trk.gz");
}

// The writer's ZIP64 records (what a whole-brain TRX past 4 GiB needs), forced on a small archive: a TRX built
// with them reads alike here and in Python's zipfile + numpy.
TEST(TractFormatsRoundTrip, Zip64TrxReadsHereAndInPython) {
  DTF_REFERENCE_PYTHON(python);
  const fs::path dir = dtf::test::scratchDir();
  const Polylines src = richLines();
  const std::string header = R"({"VOXEL_TO_RASMM": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],)"
                             R"( "DIMENSIONS": [10, 10, 10], "NB_VERTICES": )" +
                             std::to_string(src.points.size()) +
                             R"(, "NB_STREAMLINES": )" + std::to_string(src.lineCount()) + "}";
  const fs::path path = dir / "zip64.trx";
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    dtf::io::ZipWriter zip(f, path.string(), dtf::io::ZipWriter::Zip64::Always);
    zip.add("header.json", header.data(), header.size());
    zip.add("positions.3.float32", src.points.data(), src.points.size() * sizeof(glm::vec3));
    zip.add("offsets.uint32", src.offsets.data(), src.offsets.size() * 4);
    zip.finish();
  }
  // The archive really carries the ZIP64 end record and locator.
  const std::string bytes = readBytes(path.string());
  EXPECT_NE(bytes.find(std::string("PK\x06\x06", 4)), std::string::npos);
  EXPECT_NE(bytes.find(std::string("PK\x06\x07", 4)), std::string::npos);
  const Polylines here = dtf::io::readTrx(path.string());
  expectSameLines(here, src, 0, 0, "zip64.trx read here");
  const Reference r = independentRead(python, path, dir);
  expectSameLines(r.lines, src, 0, 0, "zip64.trx read by Python's zipfile");
  // Python's own integrity check passes (the CRCs and the sizes in the ZIP64 fields).
  const std::string check = python + " -c 'import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); "
                                     "sys.exit(z.testzip() is not None or len(z.namelist()) != 3)' '" +
                            path.string() + "'";
  EXPECT_EQ(std::system(check.c_str()), 0) << check;
}

// A TRX written here (stored float32, each array aligned in the file) is read in place: its positions are a
// view of the file's mapping, equal to what was written; a changed copy leaves the file as it was. Positions
// that cannot be viewed (a deflated entry) are read into memory alike.
TEST(TractFormatsTrx, StoredFloat32PositionsAreReadInPlace) {
  const fs::path dir = dtf::test::scratchDir();
  const Polylines src = richLines();
  const fs::path path = dir / "inplace.trx";
  dtf::io::writeTrx(path.string(), src, lasReference());
  Polylines read = dtf::io::readTrx(path.string());
  ASSERT_TRUE(read.points.viewed()) << "stored float32 positions are used in place";
  EXPECT_TRUE(read.points == src.points);
  EXPECT_EQ(read.offsets, src.offsets);
  Polylines copy = read;
  copy.points[0] += glm::vec3(100);
  EXPECT_FALSE(copy.points.viewed());
  EXPECT_TRUE(read.points.viewed());
  EXPECT_TRUE(read.points == src.points);
  EXPECT_TRUE(dtf::io::readTrx(path.string()).points == src.points) << "the file is unchanged";
  // The same arrays with the positions deflated are copied out of the archive.
  const std::string header = R"({"NB_VERTICES": )" + std::to_string(src.points.size()) +
                             R"(, "NB_STREAMLINES": )" + std::to_string(src.lineCount()) + "}";
  const std::string pos(reinterpret_cast<const char*>(src.points.data()), src.points.size() * 12);
  const std::string off(reinterpret_cast<const char*>(src.offsets.data()), src.offsets.size() * 4);
  const fs::path deflated = dir / "deflated.trx";
  std::ofstream(deflated, std::ios::binary)
      << dtf::test::zipArchive({{"header.json", header}, {"positions.3.float32", pos, true}, {"offsets.uint32", off}});
  const Polylines d = dtf::io::readTrx(deflated.string());
  EXPECT_FALSE(d.points.viewed());
  EXPECT_TRUE(d.points == src.points);
}
