// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric view` behaviour that needs no display: registration, help, script errors before a window
// opens, and a clear GL error (exit code 3) when no display is available.
#include "support/cli.h"
#include "support/test_env.h"

#include <fstream>
#include <gtest/gtest.h>

using dtf::test::runDtfabric;

TEST(ViewCli, HelpListsView) {
  const auto r = runDtfabric("--help", dtf::test::scratchDir());
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("\n  view "), std::string::npos) << r.out; // .ci/demo greps for '^  view '
  const auto v = runDtfabric("view --help", dtf::test::scratchDir());
  EXPECT_EQ(v.exitCode, 0);
  EXPECT_NE(v.out.find("--script FILE"), std::string::npos);
}

TEST(ViewCli, BadScriptLineFailsBeforeTheWindowWithFileAndLine) {
  const auto dir = dtf::test::scratchDir();
  const auto script = dir / "bad.txt";
  std::ofstream(script) << "# ok\nfa 0.3\nrotate 10\n";
  const auto r = runDtfabric("view --script '" + script.string() + "'", dir);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find(script.string() + ":3: usage: rotate DX DY"), std::string::npos) << r.err;
}

TEST(ViewCli, MissingScriptAndBadOptions) {
  const auto dir = dtf::test::scratchDir();
  EXPECT_EQ(runDtfabric("view --script /nonexistent/script.txt", dir).exitCode, 2);
  EXPECT_EQ(runDtfabric("view --size 10x10", dir).exitCode, 1);
  EXPECT_EQ(runDtfabric("view --surface fa=3", dir).exitCode, 1);
  EXPECT_EQ(runDtfabric("view --frobnicate 1", dir).exitCode, 1);
}

TEST(ViewCli, NoDisplayIsAGlError) {
  // With a display the viewer would open and wait for the user.
  if (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY")) GTEST_SKIP() << "a display is available";
  const auto dir = dtf::test::scratchDir();
  const auto r = runDtfabric("view", dir);
  EXPECT_EQ(r.exitCode, 3) << r.err;
  EXPECT_NE(r.err.find("GLFW"), std::string::npos) << r.err;
}
