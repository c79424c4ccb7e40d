// SPDX-License-Identifier: GPL-3.0-or-later
// JSON through the real executable: every `--json` report is one valid JSON document that carries file
// names exactly (quotes, backslashes, newlines, non-ASCII), and TRX headers are read as any valid JSON and
// refused (exit code 2, the file named) when they are not.
#include "support/cli.h"
#include "support/test_env.h"
#include "support/zip_builder.h"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

namespace {

namespace fs = std::filesystem;
using dtf::test::CliResult;
using dtf::test::runDtfabric;
using nlohmann::json;

// One shell word holding `s` exactly.
std::string word(const std::string& s) {
  std::string o = "'";
  for (char c : s)
    o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}
std::string word(const fs::path& p) {
  return word(p.string());
}

// A file name with a double and a single quote, a backslash, a newline, a tab and non-ASCII letters.
const std::string kHostile = "h \"q\" 'a' \\ b\nc\td caf\xc3\xa9 \xe6\xbc\xa2";

// stdout parsed as exactly one JSON document (fails the test otherwise).
json parsed(const CliResult& r) {
  try {
    return json::parse(r.out);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "not valid JSON: " << e.what() << "\n" << r.out;
    return json();
  }
}

std::string floats(std::initializer_list<float> v) {
  std::string s;
  for (float f : v)
    s.append(reinterpret_cast<const char*>(&f), 4);
  return s;
}

// Two streamlines of two points (float32 positions, uint32 offsets with the end entry) with `header`.
std::string trx(const std::string& header) {
  return dtf::test::zipArchive({{"header.json", header, false},
                                {"positions.3.float32", floats({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3}), false},
                                {"offsets.uint32", std::string("\0\0\0\0\2\0\0\0\4\0\0\0", 12), false}});
}

void write(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

TEST(JsonCli, TrackAndInfoCarryHostilePathsExactly) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path tensor = dir / (kHostile + ".nii.gz");
  ASSERT_EQ(runDtfabric("phantom brain --size 24 -o " + word(tensor), dir).exitCode, 0);

  const fs::path tracts = dir / (kHostile + ".tck");
  CliResult r = runDtfabric("track " + word(tensor) + " --seed-sphere 0,0,0,6 --select 20 --min-length 5 --json -o " +
                                word(tracts),
                            dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json j = parsed(r);
  EXPECT_EQ(j.value("output", ""), tracts.string());
  EXPECT_EQ(j.value("streamlines", 0), 20);
  EXPECT_EQ(j.value("integrator", ""), "rk4");
  ASSERT_TRUE(fs::exists(tracts));

  r = runDtfabric("info --json " + word(tensor), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  j = parsed(r);
  EXPECT_EQ(j.value("file", ""), tensor.string());
  EXPECT_EQ(j.value("is_tensor", false), true);
  EXPECT_EQ(j.at("dims").size(), 4u);
  EXPECT_EQ(j.at("affine").size(), 4u);

  r = runDtfabric("info " + word(tensor) + " --voxel 12,12,12 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  j = parsed(r);
  EXPECT_EQ(j.value("file", ""), tensor.string());
  EXPECT_EQ(j.at("voxel"), json::array({12, 12, 12}));
  EXPECT_EQ(j.at("eigenvectors").size(), 3u);

  r = runDtfabric("info " + word(tracts) + " --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  j = parsed(r);
  EXPECT_EQ(j.value("file", ""), tracts.string());
  EXPECT_EQ(j.value("streamlines", 0), 20);

  r = runDtfabric("check " + word(tensor) + " --json", dir);
  EXPECT_LT(r.exitCode, 3) << r.err; // a phantom may be too small to decide; the report is still JSON
  if (!r.out.empty()) {
    EXPECT_EQ(parsed(r).value("input", ""), tensor.string());
  }

  const fs::path mesh = dir / (kHostile + ".obj");
  r = runDtfabric("surface " + word(tensor) + " --slice axial:12 -o " + word(mesh) + " --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(parsed(r).value("output", ""), mesh.string());
}

TEST(JsonCli, PeaksInfoCarriesHostilePathsExactly) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path peaks = dir / (kHostile + ".nii.gz");
  ASSERT_EQ(runDtfabric("phantom crossing --crossing 70 --size 24 --layout mrtrix-peaks -o " + word(peaks), dir).exitCode, 0);
  CliResult r = runDtfabric("info " + word(peaks) + " --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json j = parsed(r);
  EXPECT_EQ(j.value("file", ""), peaks.string());
  EXPECT_EQ(j.value("is_fibres", false), true);
  r = runDtfabric("info " + word(peaks) + " --voxel 12,12,12 --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  j = parsed(r);
  EXPECT_EQ(j.value("file", ""), peaks.string());
  ASSERT_EQ(j.at("fibres").size(), 2u) << r.out;
  EXPECT_EQ(j.at("fibres").at(0).at("direction").size(), 3u);
}

// A name that is not UTF-8 (legal on Linux) cannot be carried exactly in JSON: the byte becomes U+FFFD and
// the report stays valid.
TEST(JsonCli, NamesThatAreNotUtf8StayValidJson) {
  const fs::path dir = dtf::test::scratchDir();
  const fs::path tensor = dir / "bad\xff" "name.nii.gz";
  ASSERT_EQ(runDtfabric("phantom brain --size 16 -o " + word(tensor), dir).exitCode, 0);
  const CliResult r = runDtfabric("info --json " + word(tensor), dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(parsed(r).value("file", ""), (dir / "bad\xef\xbf\xbd" "name.nii.gz").string());
}

TEST(JsonCli, BenchCheckCarriesAHostileDataPath) {
  DTF_SHARED_FILE(real, "iu_prisma_dwi");
  const fs::path dir = dtf::test::scratchDir();
  const fs::path data = dir / kHostile;
  fs::create_directories(data);
  fs::create_directory_symlink(fs::absolute(real), data / "iu_prisma_dwi");
  // PATH without MRtrix: the peer is reported absent (its note is JSON text too).
  const std::string cmd = "env PATH=" + word(dir) + " " + word(std::string(DTF_EXE)) +
                          " bench check --repeat 1 --json --data " + word(data) + " >" + word(dir / "out.json") +
                          " 2>" + word(dir / "err.txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << dtf::test::readText(dir / "err.txt");
  CliResult r;
  r.out = dtf::test::readText(dir / "out.json");
  const json j = parsed(r);
  EXPECT_EQ(j.value("data", ""), (data / "iu_prisma_dwi" / "dwi.nii.gz").string()) << r.out;
  EXPECT_EQ(j.value("peer_ran", true), false);
  EXPECT_NE(j.value("peer_note", "").find("dwigradcheck"), std::string::npos) << r.out;
}

// header.json as other writers lay it out, through the whole command.
TEST(JsonCli, TrxHeadersAnyValidJsonReadsAndMalformedIsRefused) {
  const fs::path dir = dtf::test::scratchDir();
  write(dir / "odd.trx",
        trx("\t\r\n{ \"NB_\\u0056ERTICES\" : 4.0e0 ,\"extra\":{\"s\":\"\\\"\\\\\\/\\u00e9\",\"a\":[1e-3,null,true]},"
            "\"NB_STREAMLINES\":2E0,\n\"DIMENSIONS\":[8,8,8],\"VOXEL_TO_RASMM\":[[1,0,0,0],[0,1,0,0],[0,0,1,0],"
            "[0,0,0,1]]}\n"));
  CliResult r = runDtfabric("info " + word(dir / "odd.trx") + " --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json j = parsed(r);
  EXPECT_EQ(j.value("streamlines", 0), 2);
  EXPECT_EQ(j.value("points", 0), 4);
  EXPECT_EQ(j.at("dimensions"), json::array({8, 8, 8}));

  for (const auto& [name, header, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"cut.trx", "{\"NB_STREAMLINES\": 2, \"NB_VERTICES\": 4", "bad TRX header.json: not valid JSON"},
           {"garbage.trx", "{\"NB_STREAMLINES\": 2, \"NB_VERTICES\": 4} {}", "bad TRX header.json: not valid JSON"},
           {"array.trx", "[2, 4]", "TRX header.json is not a JSON object"},
           {"text.trx", "{\"NB_STREAMLINES\": \"2\", \"NB_VERTICES\": 4}", "no valid NB_STREAMLINES"}}) {
    SCOPED_TRACE(name);
    write(dir / name, trx(header));
    r = runDtfabric("info " + word(dir / name) + " --json", dir);
    EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
    EXPECT_NE(r.err.find((dir / name).string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

} // namespace
