// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench render` end to end on a tiny viewport: the fabric and Phong figures for sphere_41k, and
// the ParaView Surface LIC peer attempted exactly when pvbatch (or pvpython) is on the PATH, as bench tracts
// does with tckgen. Either case passes: CI does not install ParaView.
#include "support/cli.h"
#include "support/gl_test.h"

#include <regex>

using dtf::test::jsonNumber;

TEST(BenchRenderCli, ReportsTheParaViewPeerExactlyWhenItIsOnThePath) {
  DTF_GL_TEST_SETUP();
  auto dir = dtf::test::scratchDir();
  auto r =
      dtf::test::runDtfabric("bench render --size 96x72 --frames 1 --only sphere_41k --no-brain --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("\"name\": \"sphere_41k\""), std::string::npos) << r.out;
  EXPECT_GT(jsonNumber(r.out, "fabric_ms"), 0) << r.out;
  const bool havePeer =
      std::system("command -v pvbatch >/dev/null 2>&1 || command -v pvpython >/dev/null 2>&1") == 0;
  const bool notOnPath = r.out.find("is not on the PATH") != std::string::npos;
  EXPECT_EQ(notOnPath, !havePeer) << r.out;
  if (!havePeer) {
    EXPECT_NE(r.out.find("\"peer\": null"), std::string::npos) << r.out;
  } else if (r.out.find("\"peer\": {") != std::string::npos) {
    EXPECT_GT(jsonNumber(r.out, "lic_default_ms"), 0) << r.out;
    EXPECT_GT(jsonNumber(r.out, "lic_one_step_ms"), 0) << r.out;
    EXPECT_GT(jsonNumber(r.out, "surface_ms"), 0) << r.out;
    EXPECT_GT(jsonNumber(r.out, "default_over_fabric"), 0) << r.out;
  } else {
    // On the PATH but unable to run here (no paraview.simple, no display): tried, and says why.
    EXPECT_NE(r.out.find("\"peer_note\""), std::string::npos) << r.out;
  }
  // --no-peer skips it in either case.
  r = dtf::test::runDtfabric("bench render --size 64x48 --frames 1 --only sphere_41k --no-brain --no-peer",
                             dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("peer: skipped (--no-peer)"), std::string::npos) << r.out;
}

// The fabric/Phong ratios of wall and CPU time, still and moving camera, per case, and the three-population
// ratio against the tensor fabric, in the table and in the JSON object.
TEST(BenchRenderCli, ReportsTheStillAndMovingRatiosAndTheThreePopulationRatio) {
  DTF_GL_TEST_SETUP();
  auto dir = dtf::test::scratchDir();
  auto r = dtf::test::runDtfabric(
      "bench render --size 96x72 --frames 2 --only sphere_41k,sphere_41k_fibres3 --no-brain --no-peer", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::regex ratio(R"(sphere_41k +still [0-9.]+ wall, [0-9.]+ (CPU|GPU) time( \([0-9.]+-[0-9.]+ over 1 )"
                         R"(blocks\))? \| moving [0-9.]+ wall, [0-9.]+ (CPU|GPU) time( \([0-9.]+-[0-9.]+\))?\n)");
  EXPECT_TRUE(std::regex_search(r.out, ratio)) << r.out;
  const std::regex three(R"(three fibre populations vs the two-direction tensor fabric[^\n]*\n +still [0-9.]+ wall, )"
                         R"([0-9.]+ (CPU|GPU) time \| moving [0-9.]+ wall)");
  EXPECT_TRUE(std::regex_search(r.out, three)) << r.out;
  const std::regex half(R"(moving as the viewer draws it[^\n]*\n[^\n]*\n +sphere_41k +1/2 [0-9.]+ wall(, [0-9.]+ )"
                        R"(CPU time \([0-9.]+-[0-9.]+\))?\n)");
  EXPECT_TRUE(std::regex_search(r.out, half)) << r.out;
  r = dtf::test::runDtfabric("bench render --size 96x72 --frames 2 --only sphere_41k --no-brain --no-peer --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_GT(jsonNumber(r.out, "moving_cpu_ms"), 0) << r.out;
  EXPECT_GT(jsonNumber(r.out, "cpu_ratio"), 0) << r.out;
  EXPECT_GT(jsonNumber(r.out, "moving_cpu_ratio"), 0) << r.out;
  // One block of two still frames and two Phong frames: its ratio is the ratio of the per-frame means.
  EXPECT_EQ(jsonNumber(r.out, "interleaved_blocks"), 1) << r.out;
  EXPECT_NEAR(jsonNumber(r.out, "cpu_ratio"), jsonNumber(r.out, "fabric_cpu_ms") / jsonNumber(r.out, "phong_cpu_ms"),
              1e-6 * jsonNumber(r.out, "cpu_ratio"))
      << r.out;
  // The moving frames alternate with Phong frames the same way: one block, the ratio of its means.
  EXPECT_NEAR(jsonNumber(r.out, "moving_cpu_ratio"),
              jsonNumber(r.out, "moving_cpu_ms") / jsonNumber(r.out, "moving_phong_cpu_ms"),
              1e-6 * jsonNumber(r.out, "moving_cpu_ratio"))
      << r.out;
  // And the half-resolution moving frames against full-resolution Phong.
  EXPECT_NEAR(jsonNumber(r.out, "moving_half_res_cpu_ratio"),
              jsonNumber(r.out, "moving_half_res_cpu_ms") / jsonNumber(r.out, "moving_half_res_phong_cpu_ms"),
              1e-6 * jsonNumber(r.out, "moving_half_res_cpu_ratio"))
      << r.out;
  // Five frames: blocks of two, two and one.
  r = dtf::test::runDtfabric("bench render --size 96x72 --frames 5 --only sphere_41k --no-brain --no-peer --json", dir);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(r.out, "interleaved_blocks"), 3) << r.out;
}
