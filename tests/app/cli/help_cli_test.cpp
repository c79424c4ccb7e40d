// SPDX-License-Identifier: GPL-3.0-or-later
// Help and README follow the declarations: every command, benchmark, script command and fabric option is
// in the help that lists it; each command's option table is what its parser accepts, what its --help and
// usage line list, and what its code reads; README.md's tables are exactly `dtfabric help --markdown`.
#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "app/viewer/view_script.h"
#include "io/model/error.h"
#include "render/fabric_options.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <cmath>
#include <gtest/gtest.h>
#include <regex>
#include <set>
#include <sstream>

namespace {

using dtf::test::runDtfabric;
using dtf::test::scratchDir;

dtf::test::CliResult run(const std::string& args) {
  return runDtfabric(args, scratchDir());
}

using dtf::app::CliOption;
using dtf::app::OptionTable;

// Every table: the commands' and the benchmarks', with the command line that selects it.
std::vector<std::pair<std::string, const OptionTable*>> allTables() {
  std::vector<std::pair<std::string, const OptionTable*>> out;
  for (const auto& c : dtf::app::commands())
    if (c.options) out.emplace_back(c.name, &c.options());
  out.emplace_back("info x.tck", &dtf::app::tractInfoOptions()); // `info` of a tractogram
  for (const auto& b : dtf::app::benchmarks())
    if (b.options) out.emplace_back("bench " + std::string(b.name), &b.options());
  return out;
}

// A value the row accepts.
std::string sampleValue(const CliOption& o) {
  using K = CliOption::Kind;
  if (o.kind == K::Choice) return o.choices.back();
  if (!o.defaultValue.empty()) return o.defaultValue;
  if (o.kind == K::Number || o.kind == K::Integer)
    return std::isfinite(o.range.lo) ? std::to_string(static_cast<long long>(std::ceil(o.range.lo)) + 1) : "1";
  if (o.check == dtf::app::checkTriple) return "1,2,3";
  if (o.check == dtf::app::checkSize) return "64x48";
  if (o.check == dtf::app::checkTensorLayout) return "fsl";
  return "x";
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

// The fabric options as table rows (render's) accept exactly what the fabric table's own parser accepts: the
// ranges come from the one declaration.
TEST(Help, FabricOptionRowsAcceptWhatTheFabricTableAccepts) {
  const auto rows = dtf::app::fabricCliOptions();
  ASSERT_EQ(rows.size(), dtf::render::fabricOptions().size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& f = dtf::render::fabricOptions()[i];
    const auto& o = rows[i];
    if (f.kind == dtf::render::FabricOption::Kind::OnOff) {
      EXPECT_EQ(o.kind, CliOption::Kind::Flag) << f.name;
      EXPECT_EQ(o.name, "no-" + std::string(f.name));
      continue;
    }
    EXPECT_EQ(o.name, f.name);
    if (f.kind == dtf::render::FabricOption::Kind::Choice) continue; // validated by FabricOption::parse
    std::vector<std::string> samples = {"x", "0", "1", "0.5", "-1", "2"};
    for (double v : {f.range.lo, f.range.hi})
      for (double d : {-1.0, -1e-3, 0.0, 1e-3, 1.0})
        samples.push_back(std::to_string(v + d));
    for (const auto& text : samples) {
      bool fabricAccepts = true, rowAccepts = true;
      try {
        f.parse(text);
      } catch (const dtf::UsageError&) {
        fabricAccepts = false;
      }
      try {
        o.validate(text);
      } catch (const dtf::UsageError&) {
        rowAccepts = false;
      }
      EXPECT_EQ(rowAccepts, fabricAccepts) << f.name << " " << text;
    }
  }
}

// Every command and every benchmark declares its options in a table, so the tests below cover them all
// (bench: its benchmarks' tables).
TEST(Help, EveryCommandAndBenchmarkHasATable) {
  for (const auto& c : dtf::app::commands())
    EXPECT_TRUE(c.options != nullptr || std::string(c.name) == "bench") << c.name << " has no option table";
  for (const auto& b : dtf::app::benchmarks())
    EXPECT_TRUE(b.options != nullptr) << "bench " << b.name << " has no option table";
  std::set<const OptionTable*> tables;
  for (const auto& [line, table] : allTables())
    tables.insert(table);
  EXPECT_EQ(allTables().size(), tables.size()) << "two entries share a table";
}

// The parser accepts every row of a table (with a value of its kind) and nothing else; a row's value is
// checked against its kind, range and choices.
TEST(Help, ParserAcceptsExactlyTheTable) {
  int rows = 0;
  for (const auto& [line, table] : allTables()) {
    const bool anyNumber = table->maxPositionals == OptionTable::kAnyNumber; // `view INPUT ...`
    const std::size_t positionals = anyNumber ? 3 : table->maxPositionals;
    for (const auto& o : table->options) {
      std::vector<std::string> argv(positionals, "POS");
      argv.push_back(o.switchName());
      if (o.kind != CliOption::Kind::Flag) argv.push_back(sampleValue(o));
      EXPECT_NO_THROW(dtf::app::ParsedOptions(*table, argv)) << line << " " << o.written();
      if (o.kind == CliOption::Kind::Number || o.kind == CliOption::Kind::Integer) {
        argv.back() = "seven";
        EXPECT_THROW(dtf::app::ParsedOptions(*table, argv), dtf::UsageError) << line << " " << o.name;
        if (std::isfinite(o.range.hi)) {
          argv.back() = std::to_string(o.range.hi + 1);
          EXPECT_THROW(dtf::app::ParsedOptions(*table, argv), dtf::UsageError) << line << " " << o.name;
        }
      }
      if (o.kind == CliOption::Kind::Choice) {
        argv.back() = "no-such-choice";
        EXPECT_THROW(dtf::app::ParsedOptions(*table, argv), dtf::UsageError) << line << " " << o.name;
      }
      if (o.kind == CliOption::Kind::Flag) {
        argv.back() += "=1";
        EXPECT_THROW(dtf::app::ParsedOptions(*table, argv), dtf::UsageError) << line << " " << o.name;
      }
      ++rows;
    }
    EXPECT_THROW(dtf::app::ParsedOptions(*table, {"--no-such-option", "1"}), dtf::UsageError) << line;
    std::vector<std::string> extra(positionals + 1, "POS");
    if (anyNumber) {
      EXPECT_EQ(dtf::app::ParsedOptions(*table, extra).positionals().size(), extra.size()) << line;
    } else {
      EXPECT_THROW(dtf::app::ParsedOptions(*table, extra), dtf::UsageError)
          << line << ": too many positionals";
    }
  }
  EXPECT_GT(rows, 80) << "the tables are almost empty";
}

// `CMD --help` is the table's help; it lists every row but internal ones, and every option it lists is a
// row; the usage line (the README's synopsis) shows every row not marked hidden.
TEST(Help, HelpListsExactlyTheTable) {
  const std::regex optionLine(R"(^  (-o|--[a-z0-9-]+)\b)");
  for (const auto& [line, table] : allTables()) {
    const std::string words = line == "info x.tck" ? "info x.tck" : line;
    const auto help = run(words + " --help");
    ASSERT_EQ(help.exitCode, 0) << line << "\n" << help.err;
    EXPECT_EQ(help.out, table->help()) << line;
    const std::string synopsis = table->synopsis();
    for (const auto& o : table->options) {
      const bool listed = help.out.find("\n  " + o.written()) != std::string::npos;
      EXPECT_EQ(listed, !o.internal) << line << " --help and " << o.written();
      if (o.synopsis != CliOption::Synopsis::Hidden) {
        EXPECT_NE(synopsis.find(o.written()), std::string::npos) << line << " usage lacks " << o.written();
      }
    }
    std::istringstream lines(help.out);
    for (std::string l; std::getline(lines, l);) {
      std::smatch m;
      if (!std::regex_search(l, m, optionLine)) continue;
      const std::string sw = m[1];
      const std::string name = sw == "-o" ? "output" : sw.substr(2);
      EXPECT_NE(table->find(name), nullptr) << line << " --help lists " << sw << ", which its table lacks";
    }
  }
}

// A command reads exactly its table: a row it never reads, or a read of a name the table lacks, throws
// std::logic_error, which the CLI reports as an unexpected error (exit code 2). Each command runs up to the
// point past its option handling (a missing input then ends it with exit code 2 naming the file).
TEST(Help, EveryCommandReadsExactlyItsTable) {
  const auto dir = scratchDir();
  const std::string missing = (dir / "no_such_input.nii.gz").string();
  const std::vector<std::string> lines = {
      "info " + missing,
      "info " + (dir / "no_such.tck").string(),
      "fit " + missing + " -o " + (dir / "o.nii.gz").string(),
      "phantom sphere --size 4 -o " + (dir / "p.nii.gz").string() + " --force",
      "surface " + missing + " --fa 0.3 -o " + (dir / "m.ply").string(),
      "render " + missing + " -o " + (dir / "r.png").string(),
      "track " + missing + " -o " + (dir / "t.tck").string(),
      "convert " + (dir / "no_such.tck").string() + " " + (dir / "o.tck").string(),
      "compare " + missing + " --tracts " + (dir / "no_such.tck").string() + " --surface fa=0.3",
      "check " + missing,
      "bids " + (dir / "no_such_bids").string() + " " + (dir / "out").string() + " participant",
      "help",
      "view --script " + (dir / "no_such_script.dtfs").string(), // stops before a window opens
      "bench bids --data " + (dir / "no_such_data").string(),
      "bench check --data " + (dir / "no_such_data").string(),
      "bench tracts --data " + (dir / "no_such_data").string(),
      "bench view --data " + (dir / "no_such_data").string(),
      // These two run to the end on small stand-ins (a phantom, synthetic tracts): a few seconds. `bench io`
      // (an HCP-sized volume and a 1 M-streamline TRX) is too slow for a test.
      "bench surfaces --repeat 1 --data " + (dir / "no_such_data").string(),
      "bench overlay --frames 1 --size 64x48 --no-reference --data " + (dir / "no_such_data").string(),
      // No case named `none`: the options read, a GL context made, an empty table printed.
      "bench render --frames 1 --size 64x48 --only none --no-brain --no-peer --data " +
          (dir / "no_such_data").string(),
  };
  for (const auto& l : lines) {
    const auto r = run(l);
    EXPECT_EQ(r.err.find("option table"), std::string::npos) << l << "\n" << r.err;
    EXPECT_EQ(r.err.find("unexpected error"), std::string::npos) << l << "\n" << r.err;
    EXPECT_NE(r.exitCode, 1) << l << ": a usage error before the options were read\n" << r.err;
  }
}

// The documentation holds the tables of `dtfabric help --markdown` verbatim, so it cannot drift from the
// code: README.md the short command table, sample_data/guide/reference.md the whole command table and the
// viewer's script table.
TEST(Help, DocumentationTablesAreHelpMarkdown) {
  const auto md = run("help --markdown");
  ASSERT_EQ(md.exitCode, 0) << md.err;
  EXPECT_EQ(md.out, dtf::app::markdownTables());
  const std::string readme = dtf::test::readText(dtf::test::sourceDir() / "README.md");
  const std::string reference = dtf::test::readText(dtf::test::sourceDir() / "sample_data/guide/reference.md");
  const auto first = md.out.find("\n\n");
  ASSERT_NE(first, std::string::npos);
  const auto second = md.out.find("\n\n", first + 2);
  ASSERT_NE(second, std::string::npos);
  const std::string shortTable = md.out.substr(0, first + 1),
                    commandsTable = md.out.substr(first + 2, second + 1 - (first + 2)),
                    scriptTable = md.out.substr(second + 2);
  EXPECT_NE(readme.find(shortTable), std::string::npos)
      << "README.md's command table differs from `dtfabric help --markdown`:\n"
      << shortTable;
  EXPECT_NE(reference.find(commandsTable), std::string::npos)
      << "sample_data/guide/reference.md's command table differs from `dtfabric help --markdown`:\n"
      << commandsTable;
  EXPECT_NE(reference.find(scriptTable), std::string::npos)
      << "sample_data/guide/reference.md's script table differs from `dtfabric help --markdown`:\n"
      << scriptTable;
  for (const auto& c : dtf::app::commands()) {
    const std::string name = c.name;
    EXPECT_NE(shortTable.find("| `dtfabric " + name + "` | "), std::string::npos) << name;
    EXPECT_NE(shortTable.find("`dtfabric " + name + " --help`, `man dtfabric-" + name + "`"), std::string::npos)
        << name;
    EXPECT_NE(commandsTable.find("`dtfabric " + name), std::string::npos) << name;
  }
  for (const auto& c : dtf::app::scriptCommands())
    EXPECT_NE(scriptTable.find("| `" + std::string(c.name)), std::string::npos) << c.name;
  for (const auto& b : dtf::app::benchmarks())
    EXPECT_NE(commandsTable.find("`" + std::string(b.name) + "`"), std::string::npos) << b.name;
  // The short table is short: one line of at most 200 characters a command.
  std::istringstream lines(shortTable);
  for (std::string line; std::getline(lines, line);)
    EXPECT_LE(line.size(), 200u) << line;
}

// The parser's rules, on a small table.
TEST(Options, ParserRules) {
  using dtf::app::ParsedOptions;
  OptionTable t;
  t.command = "demo";
  t.positionals = "IN";
  t.maxPositionals = 1;
  t.options = {CliOption::text("output", "OUT", "where").required(),
               CliOption::number("near", "MM", 2, dtf::app::atLeast(0), "distance"),
               CliOption::integer("bins", "N", 9, dtf::app::closedRange(1, 90), "bins"),
               CliOption::number("threshold", "T", static_cast<float>(0.15), dtf::app::closedRange(0, 1), "t"),
               CliOption::choice("grid", "G", {"ras", "las"}, "ras", "grid"),
               CliOption::list("label", "L", "labels"), CliOption::flag("json", "json")};
  {
    ParsedOptions p(t, {"in", "--near=3", "--near", "4", "-o", "x.png", "--label", "01", "02", "--json"});
    EXPECT_EQ(p.positional(0, "IN"), "in");
    EXPECT_EQ(p.number("near"), 4) << "the last occurrence wins";
    EXPECT_EQ(p.required("output"), "x.png");
    EXPECT_EQ(p.list("label"), (std::vector<std::string>{"01", "02"}));
    EXPECT_TRUE(p.flag("json"));
    EXPECT_EQ(p.integer("bins"), 9) << "the table's default";
    EXPECT_EQ(p.text("grid"), "ras");
    EXPECT_THROW(p.finish(), std::logic_error) << "--threshold was never read";
    p.number("threshold");
    EXPECT_NO_THROW(p.finish());
    EXPECT_THROW(p.flag("frobnicate"), std::logic_error) << "a name the table lacks";
  }
  EXPECT_EQ(ParsedOptions(t, {"--label=03"}).list("label"), (std::vector<std::string>{"03"}));
  EXPECT_EQ(ParsedOptions(t, {"--bins", "3.0"}).integer("bins"), 3);
  EXPECT_TRUE(ParsedOptions(t, {"--frobnicate", "--bins", "x", "--help"}).helpRequested()) << "help wins";
  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"--json=1"},
                                             {"--near"},
                                             {"--near", "-1"},
                                             {"--bins", "91"},
                                             {"--bins", "2.5"},
                                             {"--bins", "1e12"},
                                             {"--grid", "lps"},
                                             {"--label"},
                                             {"--label", "--json"},
                                             {"a", "b"},
                                             {"--frobnicate"}})
    EXPECT_THROW(ParsedOptions(t, bad), dtf::UsageError) << bad.front();
  try {
    ParsedOptions p(t, {"in"});
    p.required("output");
    ADD_FAILURE() << "a missing required option";
  } catch (const dtf::UsageError& e) {
    EXPECT_STREQ(e.what(), "missing -o OUT");
  }
  const std::string help = t.help();
  EXPECT_NE(help.find("usage: dtfabric demo IN -o OUT [--near MM] [--bins N] [--threshold T] [--grid G]"),
            std::string::npos)
      << help;
  EXPECT_NE(help.find("(default 2; >= 0)"), std::string::npos) << help;
  EXPECT_NE(help.find("(default 9; [1, 90])"), std::string::npos) << help;
  EXPECT_NE(help.find("(default 0.15; [0, 1])"), std::string::npos) << "a float default as written" << help;
  EXPECT_NE(help.find("(ras or las; default ras)"), std::string::npos) << help;

  // A range's unit is said in the help's facts and in the range error.
  const CliOption mm =
      CliOption::number("depth", "MM", 0, dtf::app::closedRange(-1000, 1000), "depth").measuredIn("mm");
  EXPECT_EQ(mm.rangeText(), "[-1000, 1000] mm");
  EXPECT_EQ(CliOption::number("width", "PX", 2, dtf::app::above(0), "w").measuredIn("pixels").rangeText(true),
            "> 0 pixels");
  try {
    mm.validate("5000");
    ADD_FAILURE() << "5000 is outside [-1000, 1000]";
  } catch (const dtf::UsageError& e) {
    EXPECT_STREQ(e.what(), "--depth must be in [-1000, 1000] mm, got 5000");
  }
}
