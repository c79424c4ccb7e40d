// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric info TRACTS` and `dtfabric convert` end to end on the real tractograms of other tools: header
// facts and counts in JSON, conversions between every format keeping what the target holds, atomic output
// that never replaces an input, and the exit codes for bad input (2) and usage errors (1).
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>
#include <limits>
#include <vector>

using dtf::test::jsonNumber;
using dtf::test::runDtfabric;

namespace {
std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}
bool has(const std::string& s, const std::string& what) {
  return s.find(what) != std::string::npos;
}
} // namespace

TEST(TractInfoCli, JsonKeysForEveryRealFile) {
  DTF_SHARED_FILE(dir, "niivue_tracts");
  auto scratch = dtf::test::scratchDir();
  struct Expect {
    const char* file;
    double streamlines, points;
    const char* format;
  };
  for (const Expect& e :
       {Expect{"colby.trk", 2, 32, "TrackVis v2"}, Expect{"colby.trx", 2, 32, "TRX zip"},
        Expect{"dpsv.trx", 460, 95865, "TRX zip"}, Expect{"afq_tractography.trx", 508, 141447, "TRX zip"},
        Expect{"stroke.trk.gz", 36763, 237468, "TrackVis v2 (gzip)"},
        Expect{"tract.IFOF_R.trk", 14, 168, "TrackVis"}, Expect{"tract.SLF1_R.tck", 13, 156, "MRtrix tck"},
        Expect{"tract.FAT_R.vtk", 5, 60, "legacy VTK"}}) {
    SCOPED_TRACE(e.file);
    auto r = runDtfabric("info " + q(dir / e.file) + " --json", scratch);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(jsonNumber(r.out, "streamlines"), e.streamlines) << r.out;
    EXPECT_EQ(jsonNumber(r.out, "points"), e.points);
    EXPECT_TRUE(has(r.out, std::string("\"format\": \"") + e.format)) << r.out;
    for (const char* key : {"\"dps\": [", "\"dpv\": [", "\"groups\": [", "\"length_mm\": "})
      EXPECT_TRUE(has(r.out, key)) << key;
  }
  auto colby = runDtfabric("info " + q(dir / "colby.trk") + " --json", scratch);
  EXPECT_TRUE(has(colby.out, "\"voxel_order\": \"LPS\"")) << colby.out;
  EXPECT_TRUE(has(colby.out, "\"vox_to_ras\": \"not recorded (identity used)\""));
  EXPECT_TRUE(has(colby.out, "\"dpv\": [\"effect   \", \"pval     \", \"pval_corr\"]"));
  EXPECT_TRUE(has(colby.out, "\"dimensions\": [192, 192, 55]"));
  EXPECT_TRUE(has(colby.err, "no vox_to_ras")) << colby.err;
  auto afq = runDtfabric("info " + q(dir / "afq_tractography.trx") + " --json", scratch);
  EXPECT_TRUE(has(afq.out, "\"groups\": [\"ARC_L\", \"ARC_R\"]")) << afq.out;
  EXPECT_TRUE(has(afq.out, "\"group_sizes\": {\"ARC_L\": 486, \"ARC_R\": 22}"));
  auto dpsv = runDtfabric("info " + q(dir / "dpsv.trx"), scratch);
  ASSERT_EQ(dpsv.exitCode, 0) << dpsv.err;
  EXPECT_TRUE(has(dpsv.out, "dps 'DataSetID': 460 x 1")) << dpsv.out;
  EXPECT_TRUE(has(dpsv.out, "dpv 'z': 95865 x 1"));
  EXPECT_TRUE(has(dpsv.out, "streamlines:   460 (header says 459)"));
  EXPECT_TRUE(has(dpsv.out, "uint32 (no end entry)"));
  auto mesh = runDtfabric("info " + q(dir / "issue1298.vtk"), scratch);
  EXPECT_EQ(mesh.exitCode, 2);
  EXPECT_TRUE(has(mesh.err, "issue1298.vtk") && has(mesh.err, "500 polygons")) << mesh.err;
}

// Length statistics in closed form: a .tck of two straight lines, 3 mm and 5 mm long.
TEST(TractInfoCli, LengthStatistics) {
  auto dir = dtf::test::scratchDir();
  std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: 2\nfile: . 0000000000\nEND\n";
  char off[16];
  std::snprintf(off, sizeof off, "%010zu", head.size());
  head.replace(head.find("0000000000"), 10, off);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<float> pts = {0, 0, 0, 3, 0, 0, nan, nan, nan, 0,   0,   0,
                            0, 3, 0, 0, 3, 4, nan, nan, nan, inf, inf, inf};
  std::ofstream(dir / "l.tck", std::ios::binary)
      .write((head + std::string(reinterpret_cast<const char*>(pts.data()), pts.size() * 4)).data(),
             static_cast<std::streamsize>(head.size() + pts.size() * 4));
  auto r = runDtfabric("info " + q(dir / "l.tck") + " --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(has(r.out, "\"length_mm\": {\"min\": 3.0, \"mean\": 5.0, \"median\": 5.0, \"max\": 7.0}")) << r.out;
}

// A tractogram with no streamline (a filter that kept nothing) converts to every format and reads back empty;
// `info` reports no length rather than lengths of 0.
TEST(TractConvertCli, AnEmptyTractogramRoundTripsThroughEveryFormat) {
  DTF_SHARED_FILE(ref, "iu_prisma_dwi/derived/mask.nii.gz");
  auto dir = dtf::test::scratchDir();
  std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: 0\nfile: . 0000000000\nEND\n";
  char off[16];
  std::snprintf(off, sizeof off, "%010zu", head.size());
  head.replace(head.find("0000000000"), 10, off);
  const float inf = std::numeric_limits<float>::infinity();
  const float end[3] = {inf, inf, inf};
  std::ofstream(dir / "e.tck", std::ios::binary)
      .write((head + std::string(reinterpret_cast<const char*>(end), sizeof end)).data(),
             static_cast<std::streamsize>(head.size() + sizeof end));
  for (const char* ext : {".tck", ".trk", ".trk.gz", ".trx", ".vtk", ".vtp"}) {
    SCOPED_TRACE(ext);
    const auto out = dir / (std::string("out") + ext);
    auto r = runDtfabric("convert " + q(dir / "e.tck") + " " + q(out) + " --reference " + q(ref), dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto back = runDtfabric("info " + q(out) + " --json", dir);
    ASSERT_EQ(back.exitCode, 0) << back.err;
    EXPECT_EQ(jsonNumber(back.out, "streamlines"), 0);
    EXPECT_EQ(jsonNumber(back.out, "points"), 0);
    EXPECT_TRUE(has(back.out, "\"length_mm\": null")) << back.out;
    auto text = runDtfabric("info " + q(out), dir);
    EXPECT_TRUE(has(text.out, "length (mm):   none (no streamline)")) << text.out;
  }
  // A VTK file of points without lines is still refused as tracts: it is not an empty tractogram.
  std::ofstream(dir / "pts.vtk") << "# vtk DataFile Version 4.2\npoints\nASCII\nDATASET POLYDATA\n"
                                    "POINTS 2 float\n0 0 0 1 1 1\n";
  auto pts = runDtfabric("info " + q(dir / "pts.vtk"), dir);
  EXPECT_EQ(pts.exitCode, 2);
  EXPECT_TRUE(has(pts.err, "holds no lines")) << pts.err;
}

// Every real file converts to every format; the result reads back with the same counts.
TEST(TractConvertCli, EveryRealFileToEveryFormat) {
  DTF_SHARED_FILE(dir, "niivue_tracts");
  DTF_SHARED_FILE(ref, "iu_prisma_dwi/derived/mask.nii.gz");
  auto scratch = dtf::test::scratchDir();
  int n = 0;
  for (const char* in :
       {"colby.trk", "dpsv.trx", "afq_tractography.trx", "tract.SLF1_R.tck", "tract.FAT_R.vtk"}) {
    auto info = runDtfabric("info " + q(dir / in) + " --json", scratch);
    for (const char* ext : {".tck", ".trk", ".trk.gz", ".trx", ".vtk", ".vtp"}) {
      SCOPED_TRACE(std::string(in) + " -> " + ext);
      const auto out = scratch / (std::string("c_") + in + ext);
      // .tck and .vtk sources record no space: .trk/.trx outputs need --reference.
      const bool needsRef = (std::string(in).find(".tck") != std::string::npos ||
                             std::string(in).find(".vtk") != std::string::npos) &&
                            (std::string(ext).find(".tr") != std::string::npos);
      auto r = runDtfabric(
          "convert " + q(dir / in) + " " + q(out) + (needsRef ? " --reference " + q(ref) : ""), scratch);
      ASSERT_EQ(r.exitCode, 0) << r.err;
      auto back = runDtfabric("info " + q(out) + " --json", scratch);
      ASSERT_EQ(back.exitCode, 0) << back.err;
      EXPECT_EQ(jsonNumber(back.out, "streamlines"), jsonNumber(info.out, "streamlines"));
      EXPECT_EQ(jsonNumber(back.out, "points"), jsonNumber(info.out, "points"));
      ++n;
    }
  }
  EXPECT_EQ(n, 30);
  // Without a space to write on, .tck -> .trk is a usage error naming --reference.
  auto noRef = runDtfabric("convert " + q(dir / "tract.SLF1_R.tck") + " " + q(scratch / "x.trk"), scratch);
  EXPECT_EQ(noRef.exitCode, 1);
  EXPECT_TRUE(has(noRef.err, "--reference")) << noRef.err;
  EXPECT_FALSE(std::filesystem::exists(scratch / "x.trk"));
  // Data a target cannot hold is named in a warning.
  auto drop =
      runDtfabric("convert " + q(dir / "afq_tractography.trx") + " " + q(scratch / "afq.tck"), scratch);
  EXPECT_TRUE(has(drop.err, "groups; dropped 'ARC_L', 'ARC_R'")) << drop.err;
}

TEST(TractConvertCli, NeverOverAnInputAndAtomic) {
  DTF_SHARED_FILE(tck, "niivue_tracts/tract.SLF1_R.tck");
  auto dir = dtf::test::scratchDir();
  std::filesystem::copy_file(tck, dir / "in.tck");
  auto same = runDtfabric("convert " + q(dir / "in.tck") + " " + q(dir / "in.tck") + " --force", dir);
  EXPECT_EQ(same.exitCode, 2);
  EXPECT_TRUE(has(same.err, "in.tck")) << same.err;
  std::ofstream(dir / "keep.vtk") << "precious";
  auto exists = runDtfabric("convert " + q(dir / "in.tck") + " " + q(dir / "keep.vtk"), dir);
  EXPECT_EQ(exists.exitCode, 2);
  EXPECT_TRUE(has(exists.err, "--force"));
  EXPECT_EQ(dtf::test::readText(dir / "keep.vtk"), "precious");
  // A bad input leaves no output (and no temporary file) behind.
  std::ofstream(dir / "bad.trx") << "not a zip";
  auto bad = runDtfabric("convert " + q(dir / "bad.trx") + " " + q(dir / "out.tck"), dir);
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_TRUE(has(bad.err, "bad.trx")) << bad.err;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find("out.tck"), std::string::npos) << e.path();
  auto force = runDtfabric("convert " + q(dir / "in.tck") + " " + q(dir / "keep.vtk") + " --force", dir);
  EXPECT_EQ(force.exitCode, 0) << force.err;
  auto usage = runDtfabric("convert " + q(dir / "in.tck") + " " + q(dir / "out.xyz"), dir);
  EXPECT_EQ(usage.exitCode, 1);
}
