// SPDX-License-Identifier: GPL-3.0-or-later
// Runs the real dtfabric executable for CLI tests and captures exit code, stdout and stderr.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace dtf::test {

struct CliResult {
  int exitCode = -1;
  std::string out, err;
};

inline std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Exit code and stdout + stderr interleaved as a user sees them, written through `log`.
struct CliRun {
  int code = -1;
  std::string output;
};

inline CliRun runDtfabricCombined(const std::string& args, const std::filesystem::path& log) {
  std::filesystem::create_directories(log.parent_path());
  const std::string cmd = std::string(DTF_EXE) + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log, std::ios::binary);
  r.output.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

// `args` is appended to the executable path as shell words (quote paths that may hold spaces); `shellPrefix`
// (e.g. "ulimit -v 1048576; ") comes before the command.
inline CliResult runDtfabric(const std::string& args, const std::filesystem::path& scratch,
                             const std::string& shellPrefix = "") {
  const auto outFile = scratch / "cli_stdout.txt", errFile = scratch / "cli_stderr.txt";
  std::string cmd = shellPrefix + "'" + DTF_EXE + "' " + args + " >'" + outFile.string() + "' 2>'" +
                    errFile.string() + "'";
  int status = std::system(cmd.c_str());
  CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  r.out = readText(outFile);
  r.err = readText(errFile);
  return r;
}

// The number after `"key": ` in a JSON text; -1 when absent.
inline double jsonNumber(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9.eE+-]+)"))) return -1;
  return std::stod(m[1]);
}

// `dtfabric compare TENSOR --tracts TRACTS --surface SURFACE --json` and the summary it prints.
struct CompareRun {
  CliResult cli;
  bool complete = false; // every summary field below was printed
  std::size_t points = 0;
  double mean = 0, median = 0, below = 0; // degrees, degrees, fraction below 15 degrees
};
inline CompareRun runCompare(const std::filesystem::path& tensor, const std::filesystem::path& tracts,
                             const std::string& surface, const std::filesystem::path& scratch) {
  CompareRun r;
  r.cli = runDtfabric("compare '" + tensor.string() + "' --tracts '" + tracts.string() + "' --surface " +
                          surface + " --json",
                      scratch);
  const double points = jsonNumber(r.cli.out, "points");
  r.mean = jsonNumber(r.cli.out, "mean_deg");
  r.median = jsonNumber(r.cli.out, "median_deg");
  r.below = jsonNumber(r.cli.out, "frac_below_15");
  r.complete = points >= 0 && r.mean >= 0 && r.median >= 0 && r.below >= 0;
  r.points = points >= 0 ? static_cast<std::size_t>(points) : 0;
  return r;
}

} // namespace dtf::test
