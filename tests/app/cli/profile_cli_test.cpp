// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric profile` end to end: a linear field along straight lines through real files (closed form), TRX
// groups as bundles, the table, JSON and plots, bad inputs and protected outputs, and parity with DIPY's
// afq_profile on bundles cut out of the bundled brain's tractogram (tests/support/dipy_profile.py, run by a
// python3 with DIPY: gauss within 0.02 FA and mean within 0.01 FA at every node).
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"
#include "support/chromium.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace fs = std::filesystem;
using dtf::test::runDtfabric;

namespace {

struct Row {
  std::string bundle, scalar;
  int node = 0;
  double x = 0, y = 0, z = 0, mean = 0, sd = 0, lo = 0, hi = 0;
  long streamlines = 0;
};

std::vector<std::string> splitTabs(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, '\t'))
    out.push_back(cell);
  return out;
}

// The table's rows; the header must be the documented one.
std::vector<Row> readTable(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "bundle\tscalar\tnode\tx\ty\tz\tmean\tsd\tci_low\tci_high\tstreamlines");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    const auto c = splitTabs(line);
    EXPECT_EQ(c.size(), 11u) << line;
    if (c.size() != 11) continue;
    Row r;
    r.bundle = c[0];
    r.scalar = c[1];
    r.node = std::stoi(c[2]);
    r.x = std::stod(c[3]);
    r.y = std::stod(c[4]);
    r.z = std::stod(c[5]);
    r.mean = std::stod(c[6]);
    r.sd = std::stod(c[7]);
    r.lo = std::stod(c[8]);
    r.hi = std::stod(c[9]);
    r.streamlines = std::stol(c[10]);
    rows.push_back(r);
  }
  return rows;
}

void addLine(dtf::Polylines& l, const glm::vec3& a, const glm::vec3& b, int points) {
  if (l.offsets.empty()) l.offsets.push_back(0);
  for (int i = 0; i < points; ++i)
    l.points.push_back(glm::mix(a, b, std::pow(float(i) / (points - 1), 1.5f)));
  l.offsets.push_back(static_cast<std::uint32_t>(l.points.size()));
}

// value = 0.2 + 0.01 x + 0.003 y (world mm) on a 2 mm LAS grid around the origin.
fs::path writeLinearField(const fs::path& dir) {
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(-2, 0, 0, 0);
  m[1] = glm::dvec4(0, 2, 0, 0);
  m[2] = glm::dvec4(0, 0, 2, 0);
  m[3] = glm::dvec4(60, -60, -40, 1);
  dtf::ScalarVolume v(dtf::Grid::fromAffine(glm::ivec3(61, 61, 41), m), 1);
  for (int k = 0; k < 41; ++k)
    for (int j = 0; j < 61; ++j)
      for (int i = 0; i < 61; ++i) {
        const glm::dvec3 w = v.grid.toWorld(glm::dvec3(i, j, k));
        v.at(i, j, k) = static_cast<float>(0.2 + 0.01 * w.x + 0.003 * w.y);
      }
  const fs::path p = dir / "linear.nii.gz";
  dtf::io::writeScalarVolume(p.string(), v);
  return p;
}

// Five parallel lines along x (x = -25..25) at y = ys, z = 4; the second and fourth stored backwards.
fs::path writeParallelLines(const fs::path& dir, const std::string& name, const std::vector<float>& ys) {
  dtf::Polylines l;
  for (std::size_t i = 0; i < ys.size(); ++i) {
    glm::vec3 a(-25, ys[i], 4), b(25, ys[i], 4);
    if (i % 2) std::swap(a, b);
    addLine(l, a, b, 12);
  }
  const fs::path p = dir / name;
  dtf::io::writeTck(p.string(), l);
  return p;
}

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// A python3 that imports DIPY and nibabel, or "".
std::string dipyPython() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (std::system(
            (std::string(py) + " -c 'import dipy.stats.analysis, nibabel' >/dev/null 2>&1").c_str()) == 0)
      return py;
  return "";
}

} // namespace

TEST(ProfileCli, LinearFieldAlongLinesThroughRealFiles) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path field = writeLinearField(dir);
  const std::vector<float> ys = {-4, -1, 0, 2, 8};
  const fs::path lines = writeParallelLines(dir, "along_x.tck", ys);
  for (const char* weights : {"gauss", "mean", "median"}) {
    const auto r =
        runDtfabric("profile " + q(lines) + " --scalar lin=" + q(field) + " --nodes 11 --weights " + weights +
                        " -o " + q(dir / "p.tsv") + " --force",
                    dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto rows = readTable(dir / "p.tsv");
    ASSERT_EQ(rows.size(), 11u);
    for (const auto& row : rows) {
      EXPECT_EQ(row.bundle, "along_x");
      EXPECT_EQ(row.scalar, "lin");
      EXPECT_EQ(row.streamlines, 5);
      // Oriented by the first line: node k at x = -25 + 5 k.
      const double x = -25 + 5.0 * row.node;
      EXPECT_NEAR(row.x, x, 1e-3);
      // The lines differ in y alone: the mean y 1, the median 0, and the gauss weights 1 / |y - 1| (the node
      // covariance has rank 1: the Mahalanobis distance is |y - 1| / sd(y)), normalised.
      const double gaussY =
          (-4 / 5.0 - 1 / 2.0 + 0 + 2 / 1.0 + 8 / 7.0) / (1 / 5.0 + 1 / 2.0 + 1 + 1 + 1 / 7.0);
      const std::string w = weights;
      EXPECT_NEAR(row.mean,
                  0.2 + 0.01 * x +
                      0.003 * (w == "mean"     ? 1.0
                               : w == "median" ? 0.0
                                               : gaussY),
                  1e-5);
      if (w != "gauss") {
        EXPECT_NEAR(row.sd, 0.003 * std::sqrt(20.0), 1e-5); // the sample sd of ys
      }
      EXPECT_LE(row.lo, row.mean + 1e-9);
      EXPECT_GE(row.hi, row.mean - 1e-9);
    }
  }
  // --start near x = 25 turns the profile around; the JSON carries the same rows.
  const auto r = runDtfabric("profile " + q(lines) + " --scalar lin=" + q(field) +
                                 " --nodes 11 --weights mean --start 30,0,4 --json",
                             dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["bundles"][0]["flipped"], 3);
  EXPECT_EQ(j["bundles"][0]["axis"], "right → left");
  ASSERT_EQ(j["rows"].size(), 11u);
  for (const auto& row : j["rows"]) {
    const double x = 25 - 5.0 * row["node"].get<int>();
    EXPECT_NEAR(row["x"].get<double>(), x, 1e-3);
    EXPECT_NEAR(row["mean"].get<double>(), 0.2 + 0.01 * x + 0.003, 1e-5);
  }
}

TEST(ProfileCli, SeveralBundlesGroupsTablePlotsAndJson) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path field = writeLinearField(dir);
  const fs::path a = writeParallelLines(dir, "left.tck", {-4, -1, 0, 2, 8});
  const fs::path b = writeParallelLines(dir, "right.tck", {10, 12, 13, 15});
  const auto r = runDtfabric("profile " + q(a) + " " + q(b) + " --scalar lin=" + q(field) +
                                 " --scalar again=" + q(field) + " --nodes 20 -o " + q(dir / "t.tsv") +
                                 " --plot " + q(dir / "t.png"),
                             dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readTable(dir / "t.tsv");
  ASSERT_EQ(rows.size(), 2u * 2u * 20u);
  std::map<std::string, int> perBundle;
  for (const auto& row : rows)
    ++perBundle[row.bundle + "/" + row.scalar];
  EXPECT_EQ(perBundle["left/lin"], 20);
  EXPECT_EQ(perBundle["right/again"], 20);
  // The PNG: 3 pixels per point, two panels side by side.
  std::ifstream png(dir / "t.png", std::ios::binary);
  std::string head(24, '\0');
  png.read(head.data(), 24);
  ASSERT_EQ(head.substr(1, 3), "PNG");
  const auto be32 = [&](int at) {
    return (static_cast<unsigned char>(head[at]) << 24) | (static_cast<unsigned char>(head[at + 1]) << 16) |
           (static_cast<unsigned char>(head[at + 2]) << 8) | static_cast<unsigned char>(head[at + 3]);
  };
  EXPECT_EQ(be32(16), 3 * (2 * 10 + 2 * 300));
  EXPECT_GT(be32(20), 3 * 205);
  // SVG from the same code, with the labels as text outlines.
  const auto s = runDtfabric("profile " + q(a) + " --scalar lin=" + q(field) + " -o " + q(dir / "s.tsv") +
                                 " --plot " + q(dir / "s.svg"),
                             dir);
  ASSERT_EQ(s.exitCode, 0) << s.err;
  const std::string svg = dtf::test::readText(dir / "s.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("glyph"), std::string::npos);

  // TRX groups: each a bundle named by the group, a constant field gives its value everywhere.
  dtf::Polylines g;
  for (int i = 0; i < 6; ++i)
    addLine(g, {-20, float(i), 0}, {20, float(i), 0}, 9);
  g.groups = {{"first", {0, 1, 2}}, {"second", {3, 4, 5}}};
  const fs::path trx = dir / "groups.trx";
  dtf::Grid grid = dtf::Grid::fromAffine(glm::ivec3(40), glm::dmat4(1.0));
  dtf::io::writeTrx(trx.string(), g, grid);
  const auto gr = runDtfabric("profile " + q(trx) + " --groups all --scalar lin=" + q(field) +
                                  " --weights mean --nodes 5 --json",
                              dir);
  ASSERT_EQ(gr.exitCode, 0) << gr.err;
  const auto j = nlohmann::json::parse(gr.out);
  ASSERT_EQ(j["bundles"].size(), 2u);
  EXPECT_EQ(j["bundles"][0]["name"], "first");
  EXPECT_EQ(j["bundles"][1]["name"], "second");
  EXPECT_EQ(j["bundles"][1]["streamlines"], 3);
  for (const auto& row : j["rows"]) {
    const double y = row["bundle"] == "first" ? 1.0 : 4.0;
    EXPECT_NEAR(row["mean"].get<double>(), 0.2 + 0.01 * row["x"].get<double>() + 0.003 * y, 1e-5);
  }
  const auto one =
      runDtfabric("profile " + q(trx) + " --groups second --scalar lin=" + q(field) + " --json", dir);
  ASSERT_EQ(one.exitCode, 0) << one.err;
  EXPECT_EQ(nlohmann::json::parse(one.out)["bundles"].size(), 1u);
  const auto missing =
      runDtfabric("profile " + q(trx) + " --groups third --scalar lin=" + q(field) + " --json", dir);
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.err.find("groups.trx: no group 'third' (groups: first, second)"), std::string::npos)
      << missing.err;
  // Names two bundles would share are qualified: files by their folder, groups by their file.
  fs::create_directories(dir / "patient");
  fs::create_directories(dir / "control");
  writeParallelLines(dir / "patient", "cst.tck", {0, 1, 2});
  writeParallelLines(dir / "control", "cst.tck", {0, 1, 3});
  fs::copy_file(trx, dir / "again.trx");
  const auto files =
      runDtfabric("profile " + q(dir / "patient" / "cst.tck") + " " + q(dir / "control" / "cst.tck") +
                      " --scalar lin=" + q(field) + " --nodes 3 --json",
                  dir);
  ASSERT_EQ(files.exitCode, 0) << files.err;
  const auto fj = nlohmann::json::parse(files.out);
  EXPECT_EQ(fj["bundles"][0]["name"], "patient/cst");
  EXPECT_EQ(fj["bundles"][1]["name"], "control/cst");
  const auto groups = runDtfabric("profile " + q(trx) + " " + q(dir / "again.trx") +
                                      " --groups first --scalar lin=" + q(field) + " --nodes 3 --json",
                                  dir);
  ASSERT_EQ(groups.exitCode, 0) << groups.err;
  const auto gj = nlohmann::json::parse(groups.out);
  EXPECT_EQ(gj["bundles"][0]["name"], "groups/first");
  EXPECT_EQ(gj["bundles"][1]["name"], "again/first");
  const auto none =
      runDtfabric("profile " + q(a) + " --groups all --scalar lin=" + q(field) + " --json", dir);
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_NE(none.err.find("left.tck: has no groups"), std::string::npos) << none.err;
}

TEST(ProfileCli, BadInputsExitTwoNamingTheFileAndOutputsAreProtected) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path field = writeLinearField(dir);
  const fs::path lines = writeParallelLines(dir, "lines.tck", {0, 1, 2});
  dtf::Polylines empty;
  empty.offsets = {0};
  dtf::io::writeTck((dir / "empty.tck").string(), empty);
  const std::string out = " -o " + q(dir / "o.tsv");
  struct Case {
    std::string args;
    int code;
    std::string says;
  };
  const std::vector<Case> cases = {
      {q(dir / "empty.tck") + " --scalar f=" + q(field) + out, 2, "empty.tck: the bundle has no streamlines"},
      {q(dir / "nothing.tck") + " --scalar f=" + q(field) + out, 2, "nothing.tck"},
      {q(lines) + " --scalar f=" + q(dir / "missing.nii.gz") + out, 2, "missing.nii.gz"},
      {q(lines) + " --scalar f=" + q(lines) + out, 2, "lines.tck"},
      {q(lines) + " --scalar =" + q(field) + out, 2, "no NAME before '='"},
      {q(lines) + " --scalar f=" + out, 2, "no IMAGE after '='"},
      {q(lines) + " --scalar t1" + out, 2, "--scalar 't1': not fa, md, ad or rd"},
      {q(lines) + " --scalar fa" + out, 1, "give --tensor T"},
      {q(lines) + " --scalar f=" + q(field) + " --scalar f=" + q(field) + out, 1, "'f' is given twice"},
      {q(lines) + " --scalar f=" + q(field) + out + " --plot " + q(dir / "p.jpg"), 1, ".png or .svg"},
      {q(lines) + " --scalar f=" + q(field) + out + " --start 1,2", 1, "--start '1,2'"},
      {q(lines) + " --scalar f=" + q(field), 1, "missing -o"},
      {"--scalar f=" + q(field) + " " + q(lines) + out, 1, "is a tract file"},
      {q(lines) + " --scalar f=" + q(field) + " -o " + q(lines), 2, "lines.tck"},
      {q(lines) + " --scalar f=" + q(field) + " -o " + q(field) + " --force", 2, "linear.nii.gz"},
      {q(lines) + " --scalar f=" + q(field) + out + " --plot " + q(dir / "o.tsv.png") + " --nodes 1", 1,
       "--nodes"},
  };
  const std::string before = dtf::test::readText(lines);
  for (const auto& c : cases) {
    const auto r = runDtfabric("profile " + c.args, dir);
    EXPECT_EQ(r.exitCode, c.code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir / "o.tsv")) << c.args;
  }
  EXPECT_EQ(dtf::test::readText(lines), before);
  // A multi-volume image is not a scalar.
  dtf::ScalarVolume four(dtf::Grid::fromAffine(glm::ivec3(4), glm::dmat4(1.0)), 3);
  dtf::io::writeScalarVolume((dir / "three.nii.gz").string(), four);
  const auto three = runDtfabric("profile " + q(lines) + " --scalar v=" + q(dir / "three.nii.gz") + out, dir);
  EXPECT_EQ(three.exitCode, 2);
  EXPECT_NE(three.err.find("three.nii.gz: has 3 values per voxel"), std::string::npos) << three.err;
  // An existing output stays unless --force.
  std::ofstream(dir / "o.tsv") << "keep";
  const auto kept = runDtfabric("profile " + q(lines) + " --scalar f=" + q(field) + out, dir);
  EXPECT_EQ(kept.exitCode, 2);
  EXPECT_EQ(dtf::test::readText(dir / "o.tsv"), "keep");
  EXPECT_EQ(runDtfabric("profile " + q(lines) + " --scalar f=" + q(field) + out + " --force", dir).exitCode,
            0);
  EXPECT_NE(dtf::test::readText(dir / "o.tsv"), "keep");
}

// fa from the tensor (fitted by DIPY, FA computed here) against DIPY's own FA map, sampled the same way.
TEST(ProfileCli, TensorFaMatchesTheFaMap) {
  DTF_SHARED_FILE(tracts, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(tensor, "iu_prisma_dwi/derived/dti_tensor.nii.gz");
  DTF_SHARED_FILE(faMap, "iu_prisma_dwi/derived/dti_FA.nii.gz");
  const fs::path dir = dtf::test::scratchDir();
  const auto r =
      runDtfabric("profile " + q(tracts) + " --scalar fa --scalar md --scalar dipy_fa=" + q(faMap) +
                      " --tensor " + q(tensor) + " --bootstrap 50 -o " + q(dir / "fa.tsv"),
                  dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::map<std::string, std::vector<Row>> by;
  for (const auto& row : readTable(dir / "fa.tsv"))
    by[row.scalar].push_back(row);
  ASSERT_EQ(by["fa"].size(), 100u);
  for (std::size_t k = 0; k < 100; ++k) {
    EXPECT_NEAR(by["fa"][k].mean, by["dipy_fa"][k].mean, 2e-3) << k;
    EXPECT_GT(by["md"][k].mean, 3e-4);
    EXPECT_LT(by["md"][k].mean, 2e-3);
    EXPECT_EQ(by["fa"][k].streamlines, 2000);
  }
}

// Bundles cut out of the bundled brain's 2000 streamlines by spheres (the right and left corticospinal tracts
// at the cerebral peduncle / internal capsule, the body of the corpus callosum at the midline), profiled by
// DIPY 1.6 and by dtfabric on DIPY's FA map.
TEST(ProfileCli, AgreesWithDipyAfqProfile) {
  DTF_SHARED_FILE(tracts, "iu_prisma_dwi/derived/tracks_det.tck");
  DTF_SHARED_FILE(faMap, "iu_prisma_dwi/derived/dti_FA.nii.gz");
  const std::string python = dipyPython();
  if (python.empty()) {
    if (dtf::test::envFlag("DTF_REQUIRE_TOOLS"))
      FAIL() << "python3 with DIPY is missing (.ci/setup installs python3-dipy)";
    GTEST_SKIP() << "python3 with DIPY is missing (Debian package python3-dipy; CI requires it)";
  }
  const fs::path dir = dtf::test::scratchDir();
  const std::vector<std::pair<std::string, std::string>> bundles = {{"cst_right", "18,3.721,21.604,5"},
                                                                    {"cst_left", "-19.5,5.221,21.604,5"},
                                                                    {"cc_body", "0,21.721,42.604,4"}};
  for (const auto& [name, spheres] : bundles) {
    const fs::path bundle = dir / (name + ".tck"), ref = dir / (name + "_dipy.tsv");
    const std::string cmd = python + " " + q(dtf::test::sourceDir() / "tests/support/dipy_profile.py") + " " +
                            q(tracts) + " " + q(faMap) + " '" + spheres + "' " + q(bundle) + " " + q(ref);
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(ref);
    std::string first, header, line;
    std::getline(in, first);
    std::getline(in, header);
    std::vector<std::array<double, 3>> dipy; // gauss, mean, full-covariance gauss
    while (std::getline(in, line)) {
      const auto c = splitTabs(line);
      dipy.push_back({std::stod(c[1]), std::stod(c[2]), std::stod(c[3])});
    }
    ASSERT_EQ(dipy.size(), 100u);
    long count = 0, flipped = 0;
    ASSERT_EQ(std::sscanf(first.c_str(), "# streamlines %ld flipped %ld", &count, &flipped), 2) << first;
    ASSERT_GE(count, 15) << name;

    double maxGauss = 0, maxMean = 0, maxFull = 0;
    for (const char* weights : {"gauss", "mean"}) {
      const fs::path table = dir / (name + "_" + weights + ".tsv");
      const auto r = runDtfabric("profile " + q(bundle) + " --scalar fa=" + q(faMap) + " --weights " +
                                     weights + " -o " + q(table) + " --json",
                                 dir);
      ASSERT_EQ(r.exitCode, 0) << r.err;
      const auto j = nlohmann::json::parse(r.out);
      EXPECT_EQ(j["bundles"][0]["streamlines"], count);
      EXPECT_EQ(j["bundles"][0]["flipped"], flipped) << name; // the same streamlines turned as DIPY turns
      const auto rows = readTable(table);
      ASSERT_EQ(rows.size(), 100u);
      for (std::size_t k = 0; k < 100; ++k) {
        if (std::string(weights) == "gauss") {
          maxGauss = std::max(maxGauss, std::abs(rows[k].mean - dipy[k][0]));
          maxFull = std::max(maxFull, std::abs(rows[k].mean - dipy[k][2]));
        } else {
          maxMean = std::max(maxMean, std::abs(rows[k].mean - dipy[k][1]));
        }
        EXPECT_EQ(rows[k].streamlines, count);
      }
    }
    EXPECT_LT(maxGauss, 0.02) << name;
    EXPECT_LT(maxMean, 0.01) << name;
    // Against the same weights with the full covariance, and DIPY's own mean: the same sampling and
    // resampling, to float precision.
    EXPECT_LT(maxFull, 1e-4) << name;
    EXPECT_LT(maxMean, 1e-4) << name;
    std::printf("%s: %ld streamlines; max |dtfabric - DIPY| over nodes: gauss %.4g, mean %.3g; gauss vs "
                "full-covariance reference %.3g\n",
                name.c_str(), count, maxGauss, maxMean, maxFull);
    RecordProperty(name + "_max_gauss_diff", std::to_string(maxGauss));
    RecordProperty(name + "_max_mean_diff", std::to_string(maxMean));
  }
}
