// Help and README follow the declarations: every command, benchmark, script command and fabric option is
// in the help that lists it, every flag a command reads is in its --help, and README.md's tables are
// exactly `dtfabric help --markdown`.
#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "app/viewer/view_script.h"
#include "render/fabric_options.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>
#include <regex>
#include <set>

namespace {

using dtf::test::runDtfabric;
using dtf::test::scratchDir;

dtf::test::CliResult run(const std::string& args) {
  return runDtfabric(args, scratchDir());
}

// The option names a command's source reads through Args (get, getOr, getDouble, getInt, flag).
std::set<std::string> flagsRead(const std::filesystem::path& source) {
  const std::string text = dtf::test::readText(source);
  std::set<std::string> names;
  const std::regex call(R"(args\.(?:get|getOr|getDouble|getInt|flag)\(\"([a-z0-9-]+)\")");
  for (std::sregex_iterator it(text.begin(), text.end(), call), end; it != end; ++it)
    if ((*it)[1] != "help") names.insert((*it)[1]);
  return names;
}

} // namespace

TEST(Help, ListsEveryCommandAndBenchmark) {
  const auto top = run("--help");
  ASSERT_EQ(top.exitCode, 0) << top.err;
  for (const auto& c : dtf::app::commands())
    EXPECT_NE(top.out.find("  " + std::string(c.name) + " "), std::string::npos) << c.name;
  const auto bench = run("bench --help");
  ASSERT_EQ(bench.exitCode, 0) << bench.err;
  EXPECT_GE(dtf::app::benchmarks().size(), 6u);
  for (const auto& b : dtf::app::benchmarks()) {
    EXPECT_NE(top.out.find(b.name), std::string::npos) << "dtfabric --help misses benchmark " << b.name;
    EXPECT_NE(bench.out.find("  " + std::string(b.name) + " "), std::string::npos) << b.name;
  }
}

TEST(Help, ViewHelpListsEveryScriptCommand) {
  const auto view = run("view --help");
  ASSERT_EQ(view.exitCode, 0) << view.err;
  EXPECT_GE(dtf::app::scriptCommands().size(), 25u);
  for (const auto& c : dtf::app::scriptCommands())
    EXPECT_NE(view.out.find("\n  " + std::string(c.name) + " "), std::string::npos) << c.name;
}

TEST(Help, RenderHelpListsEveryFabricOption) {
  const auto render = run("render --help");
  ASSERT_EQ(render.exitCode, 0) << render.err;
  for (const auto& o : dtf::render::fabricOptions())
    EXPECT_NE(render.out.find(o.cliSynopsis()), std::string::npos) << o.name;
}

// Each flag a command's source reads is named in its --help (benchmarks: in `bench NAME --help`).
TEST(Help, EveryFlagACommandReadsIsInItsHelp) {
  const auto root = dtf::test::sourceDir();
  int checked = 0;
  for (const auto& c : dtf::app::commands()) {
    const auto source = root / "app" / "cli" / ("cmd_" + std::string(c.name) + ".cpp");
    if (!std::filesystem::exists(source)) continue; // help lives in cli.cpp and reads no flag
    const auto help = run(std::string(c.name) + " --help");
    for (const auto& f : flagsRead(source)) {
      const std::string written = f == "output" ? "-o " : "--" + f; // Args reads -o as --output
      EXPECT_NE(help.out.find(written), std::string::npos)
          << "dtfabric " << c.name << " --help misses " << written;
      ++checked;
    }
  }
  for (const auto& b : dtf::app::benchmarks()) {
    const auto source = root / "app" / "bench" / ("bench_" + std::string(b.name) + ".cpp");
    ASSERT_TRUE(std::filesystem::exists(source)) << source;
    const auto help = run("bench " + std::string(b.name) + " --help");
    for (const auto& f : flagsRead(source)) {
      const std::string written = f == "output" ? "-o " : "--" + f;
      EXPECT_NE(help.out.find(written), std::string::npos)
          << "dtfabric bench " << b.name << " --help misses " << written;
      ++checked;
    }
  }
  EXPECT_GT(checked, 60) << "the scan found almost no flags: are the sources where expected?";
}

// README.md holds the tables of `dtfabric help --markdown` verbatim, so the README cannot drift from the
// code.
TEST(Help, ReadmeTablesAreHelpMarkdown) {
  const auto md = run("help --markdown");
  ASSERT_EQ(md.exitCode, 0) << md.err;
  EXPECT_EQ(md.out, dtf::app::markdownTables());
  const std::string readme = dtf::test::readText(dtf::test::sourceDir() / "README.md");
  const auto split = md.out.find("\n\n");
  ASSERT_NE(split, std::string::npos);
  const std::string commandsTable = md.out.substr(0, split + 1), scriptTable = md.out.substr(split + 2);
  EXPECT_NE(readme.find(commandsTable), std::string::npos)
      << "README.md's command table differs from `dtfabric help --markdown`:\n"
      << commandsTable;
  EXPECT_NE(readme.find(scriptTable), std::string::npos)
      << "README.md's script table differs from `dtfabric help --markdown`:\n"
      << scriptTable;
  for (const auto& c : dtf::app::commands())
    EXPECT_NE(commandsTable.find("`dtfabric " + std::string(c.name)), std::string::npos) << c.name;
  for (const auto& c : dtf::app::scriptCommands())
    EXPECT_NE(scriptTable.find("| `" + std::string(c.name)), std::string::npos) << c.name;
  for (const auto& b : dtf::app::benchmarks())
    EXPECT_NE(commandsTable.find("`" + std::string(b.name) + "`"), std::string::npos) << b.name;
}
