// SPDX-License-Identifier: GPL-3.0-or-later
// Running another program without a shell: hostile arguments arrive unchanged and run nothing, exit codes
// and signals come back, stdout and stderr go where asked, the environment is extended, a missing program
// is 127, and findOnPath finds executables only.
#include "io/formats/process.h"
#include "support/test_env.h"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <sys/stat.h>

namespace fs = std::filesystem;
using namespace dtf;

namespace {

std::string readAll(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

} // namespace

TEST(Process, HostileArgumentsArriveAsTheyAreAndRunNothing) {
  const fs::path dir = test::scratchDir();
  const fs::path pwned = dir / "PWNED";
  const std::vector<std::string> hostile = {
      "$(touch " + pwned.string() + ")", "`touch " + pwned.string() + "`", "a b 'c' \"d\"; touch " + pwned.string(),
      "<b>markup</b> & | > x", "", "new\nline"};
  for (const auto& arg : hostile) {
    SCOPED_TRACE(arg);
    const fs::path out = dir / "out.txt";
    EXPECT_EQ(io::runProgram({"printf", "%s", arg}, {out.string(), "/dev/null", {}}), 0);
    EXPECT_EQ(readAll(out), arg);
  }
  EXPECT_FALSE(fs::exists(pwned)) << "an argument ran as a command";
  EXPECT_FALSE(fs::exists(dir / "x"));
}

TEST(Process, ExitCodesSignalsAndMissingPrograms) {
  EXPECT_EQ(io::runProgram({"sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(io::runProgram({"true"}), 0);
  EXPECT_EQ(io::runProgram({"sh", "-c", "kill -TERM $$"}), 128 + 15);
  EXPECT_EQ(io::runProgram({"dtfabric-no-such-program-xyz"}), 127);
  EXPECT_EQ(io::runProgram({}), 127);
}

TEST(Process, OutputsEnvironmentAndStdin) {
  const fs::path dir = test::scratchDir();
  const fs::path out = dir / "o.txt", err = dir / "e.txt", both = dir / "both.txt";
  EXPECT_EQ(io::runProgram({"sh", "-c", "echo out; echo err >&2"}, {out.string(), err.string(), {}}), 0);
  EXPECT_EQ(readAll(out), "out\n");
  EXPECT_EQ(readAll(err), "err\n");
  EXPECT_EQ(io::runProgram({"sh", "-c", "echo out; echo err >&2"}, {both.string(), both.string(), {}}), 0);
  EXPECT_EQ(readAll(both), "out\nerr\n");
  EXPECT_EQ(io::runProgram({"sh", "-c", "printf %s \"$DTF_PROCESS_TEST\""},
                           {out.string(), "/dev/null", {"DTF_PROCESS_TEST=a b $(c)"}}),
            0);
  EXPECT_EQ(readAll(out), "a b $(c)");
  // Stdin is empty: `cat` ends at once instead of waiting for this process's input.
  EXPECT_EQ(io::runProgram({"cat"}, {out.string(), "/dev/null", {}}), 0);
  EXPECT_EQ(readAll(out), "");
}

TEST(Process, FindOnPathFindsExecutableFilesOnly) {
  EXPECT_NE(io::findOnPath("sh"), "");
  EXPECT_EQ(io::findOnPath("dtfabric-no-such-program-xyz"), "");
  const fs::path dir = test::scratchDir();
  std::ofstream(dir / "plain") << "not executable";
  fs::create_directories(dir / "adir");
  const std::string old = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", dir.c_str(), 1);
  EXPECT_EQ(io::findOnPath("plain"), "");
  EXPECT_EQ(io::findOnPath("adir"), "");
  ::chmod((dir / "plain").c_str(), 0755);
  EXPECT_EQ(io::findOnPath("plain"), (dir / "plain").string());
  ::setenv("PATH", old.c_str(), 1);
}
