// Runs the real dtfabric executable for CLI tests and captures exit code, stdout and stderr.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

// `args` is appended to the executable path as shell words (quote paths that may hold spaces).
inline CliResult runDtfabric(const std::string& args, const std::filesystem::path& scratch) {
  const auto outFile = scratch / "cli_stdout.txt", errFile = scratch / "cli_stderr.txt";
  std::string cmd = std::string("'") + DTF_EXE + "' " + args + " >'" + outFile.string() + "' 2>'" + errFile.string() + "'";
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

} // namespace dtf::test
