// SPDX-License-Identifier: GPL-3.0-or-later
// The man pages and the bash completion follow the option tables: every command has a page naming every
// listed option of its tables, man formats each page without a warning, the pages and the completion the
// build installs (build/manual) are what the tables give now, and bash completes commands, benchmarks,
// each command's flags, a Choice option's values, file names after a path option and nothing after a number.
#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "app/cli/manual.h"
#include "app/command/options.h"
#include "support/cli.h"
#include "support/test_env.h"

#include <gtest/gtest.h>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace {

namespace fs = std::filesystem;
using dtf::app::CliOption;
using dtf::app::OptionTable;

// The tables behind each completion key ("render", "bench io"); `info` also takes the tractogram table's.
std::vector<std::pair<std::string, std::vector<const OptionTable*>>> completionKeys() {
  std::vector<std::pair<std::string, std::vector<const OptionTable*>>> out;
  for (const auto& c : dtf::app::commands()) {
    if (std::string(c.name) == "bench") {
      for (const auto& b : dtf::app::benchmarks())
        out.push_back({"bench " + std::string(b.name), {&b.options()}});
      continue;
    }
    std::vector<const OptionTable*> tables;
    if (c.options) tables.push_back(&c.options());
    if (std::string(c.name) == "info") tables.push_back(&dtf::app::tractInfoOptions());
    out.push_back({c.name, tables});
  }
  return out;
}

std::string roffSwitch(const std::string& sw) {
  std::string out;
  for (char ch : sw) out += ch == '-' ? std::string("\\-") : std::string(1, ch);
  return out;
}

// The output of a shell command.
std::string shell(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
  }
  return out;
}

std::set<std::string> splitWords(const std::string& text) {
  std::set<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;) out.insert(w);
  return out;
}

} // namespace

TEST(ManPages, EveryCommandHasAPageNamingEveryOption) {
  const auto names = dtf::app::manPageNames();
  ASSERT_EQ(names.size(), dtf::app::commands().size() + 1);
  const std::string overview = dtf::app::manPage("dtfabric");
  for (const auto& c : dtf::app::commands()) {
    EXPECT_NE(overview.find("\\fBdtfabric " + roffSwitch(c.name) + "\\fR"), std::string::npos) << c.name;
    const std::string page = dtf::app::manPage("dtfabric-" + std::string(c.name));
    std::string upper = "-" + std::string(c.name);
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    EXPECT_NE(page.find(".TH DTFABRIC" + roffSwitch(upper) + " 1"), std::string::npos) << c.name;
    for (const auto& [key, tables] : completionKeys()) {
      if (key != c.name && key.rfind(std::string(c.name) + " ", 0) != 0) continue;
      for (const auto* t : tables)
        for (const auto& o : t->options) {
          const bool listed = page.find("\\fB" + roffSwitch(o.switchName()) + "\\fR") != std::string::npos;
          EXPECT_EQ(listed, !o.internal) << "dtfabric-" << c.name << " and " << o.switchName();
        }
    }
  }
  EXPECT_THROW(dtf::app::manPage("dtfabric-nosuch"), std::exception);
}

TEST(ManPages, ManFormatsEveryPageWithoutWarnings) {
  const fs::path dir = dtf::test::scratchDir() / "man1";
  fs::create_directories(dir);
  for (const auto& name : dtf::app::manPageNames()) {
    const fs::path file = dir / (name + ".1");
    std::ofstream(file) << dtf::app::manPage(name);
    // As lintian runs it; the page's text as `man` shows it.
    const std::string warnings = shell("LC_ALL=C.UTF-8 MANROFFSEQ='' MANWIDTH=80 man --warnings -E UTF-8 -l -Tutf8 -Z '" +
                                       file.string() + "' 2>&1 >/dev/null");
    EXPECT_EQ(warnings, "") << name;
    const std::string text = shell("LC_ALL=C.UTF-8 MANWIDTH=200 man -l -P cat '" + file.string() + "' 2>/dev/null");
    EXPECT_NE(text.find("NAME"), std::string::npos) << name;
    EXPECT_NE(text.find(name), std::string::npos) << name;
  }
  const std::string render =
      shell("LC_ALL=C.UTF-8 MANWIDTH=300 man -l -P cat '" + (dir / "dtfabric-render.1").string() + "' 2>/dev/null");
  // Option names print with ASCII hyphens (copyable), the help with its default.
  const CliOption* size = dtf::app::renderOptions().find("size");
  ASSERT_NE(size, nullptr);
  EXPECT_NE(render.find(size->written()), std::string::npos) << render;
  EXPECT_NE(render.find("default " + size->defaultValue), std::string::npos) << render;
}

TEST(ManPages, TheBuildInstallsWhatTheTablesGive) {
  const fs::path manual = dtf::test::binaryDir() / "manual";
  std::size_t pages = 0;
  for (const auto& name : dtf::app::manPageNames()) {
    const fs::path gz = manual / "man1" / (name + ".1.gz");
    ASSERT_TRUE(fs::exists(gz)) << gz << " (built by the dtf_manual target)";
    EXPECT_EQ(shell("gzip -dc '" + gz.string() + "'"), dtf::app::manPage(name)) << name << " is stale";
    // gzip -9n: no file name, no time stamp.
    std::ifstream in(gz, std::ios::binary);
    char head[8] = {};
    in.read(head, 8);
    EXPECT_EQ(head[3] & 0x08, 0) << name << ".1.gz stores a file name";
    EXPECT_EQ(head[4] | head[5] | head[6] | head[7], 0) << name << ".1.gz stores a time stamp";
    ++pages;
  }
  EXPECT_EQ(pages, dtf::app::commands().size() + 1);
  std::size_t installed = 0;
  for (const auto& e : fs::directory_iterator(manual / "man1")) installed += e.path().extension() == ".gz";
  EXPECT_EQ(installed, pages) << "a page of a removed command is left in " << manual / "man1";
  EXPECT_EQ(dtf::test::readText(manual / "completions" / "dtfabric"), dtf::app::bashCompletion());
  // The executable prints the same.
  const auto run = dtf::test::runDtfabric("help --bash-completion", dtf::test::scratchDir());
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(run.out, dtf::app::bashCompletion());
}

TEST(Completion, BashCompletesCommandsFlagsChoicesAndFiles) {
  const fs::path dir = dtf::test::scratchDir() / "completion";
  fs::remove_all(dir);
  fs::create_directories(dir / "files");
  std::ofstream(dir / "dtfabric.bash") << dtf::app::bashCompletion();
  std::ofstream(dir / "files" / "brain_dwi.nii.gz") << "x";

  // One bash run answers every query: "ID<TAB>the sorted COMPREPLY".
  std::map<std::string, std::set<std::string>> expected;
  std::string script = "cd '" + (dir / "files").string() + "'\nsource '" + (dir / "dtfabric.bash").string() +
                       "'\nq() { id=$1; shift; COMP_WORDS=(\"$@\"); COMP_CWORD=$(( $# - 1 )); _dtfabric; "
                       "printf '%s\\t%s\\n' \"$id\" \"${COMPREPLY[*]}\"; }\n";
  auto query = [&](const std::string& id, const std::string& words, std::set<std::string> want) {
    script += "q '" + id + "' " + words + "\n";
    expected[id] = std::move(want);
  };
  query("command", "dtfabric ren", {"render"});
  std::set<std::string> all = {"--help", "--version"};
  for (const auto& c : dtf::app::commands()) all.insert(c.name);
  query("commands", "dtfabric ''", all);
  std::set<std::string> benches = {"--help"};
  for (const auto& b : dtf::app::benchmarks()) benches.insert(b.name);
  query("benchmarks", "dtfabric bench ''", benches);
  query("positional", "dtfabric render brain", {"brain_dwi.nii.gz"});

  int n = 0;
  for (const auto& [key, tables] : completionKeys()) {
    std::set<std::string> flags = {"--help"};
    for (const auto* t : tables)
      for (const auto& o : t->options) {
        if (o.internal || !flags.insert(o.switchName()).second) continue; // the first table's row wins
        const std::string id = std::to_string(n++);
        const std::string before = "dtfabric " + key + " " + o.switchName();
        switch (o.kind) {
        case CliOption::Kind::Choice:
          query(id, before + " ''", {o.choices.begin(), o.choices.end()});
          break;
        case CliOption::Kind::Number:
        case CliOption::Kind::Integer:
          query(id, before + " ''", {});
          break;
        case CliOption::Kind::Text:
        case CliOption::Kind::List:
          query(id, before + " brain", {"brain_dwi.nii.gz"});
          break;
        case CliOption::Kind::Flag:
          break;
        }
      }
    query(key + " flags", "dtfabric " + key + " -", flags);
  }
  std::ofstream(dir / "queries.sh") << script;
  const std::string out = shell("bash '" + (dir / "queries.sh").string() + "' 2>&1");
  std::map<std::string, std::set<std::string>> got;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    const auto tab = line.find('\t');
    ASSERT_NE(tab, std::string::npos) << "bash printed: " << line;
    got[line.substr(0, tab)] = splitWords(line.substr(tab + 1));
  }
  ASSERT_EQ(got.size(), expected.size()) << out;
  for (const auto& [id, want] : expected) EXPECT_EQ(got[id], want) << "query " << id;
  EXPECT_GT(n, 50); // the queries cover the tables' rows
}
