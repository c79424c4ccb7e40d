// Minimal command-line parsing for the dtfabric subcommands: positionals, `--key value`, `--key=value`
// and boolean flags. Unknown or unused options are a UsageError (exit code 1).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace dtf::app {

class Args {
public:
  // `flags` lists the options that take no value (e.g. "json", "force").
  Args(const std::vector<std::string>& argv, const std::set<std::string>& flags);

  const std::vector<std::string>& positionals() const { return positionals_; }
  // Positional n or a UsageError naming `what`.
  const std::string& positional(std::size_t n, const std::string& what) const;
  bool flag(const std::string& name);
  std::optional<std::string> get(const std::string& name);
  std::string getOr(const std::string& name, const std::string& def);
  double getDouble(const std::string& name, double def);
  int getInt(const std::string& name, int def);
  // Throws UsageError if an option was given that no get()/flag() call asked for.
  void finish() const;

private:
  std::vector<std::string> positionals_;
  std::vector<std::pair<std::string, std::string>> options_;
  std::set<std::string> flagsGiven_;
  std::set<std::string> used_;
};

// --surface SPEC or one of its shorthands (--fa T, --slice AXIS[:I], --fibre-surface, --fibre-surface-voxel)
// as a surface spec; nullopt when none is given; UsageError for more than one.
std::optional<std::string> surfaceArgument(Args& args);

// Parses "W x H" such as "1024x768".
void parseSize(const std::string& text, int& w, int& h);
// Parses "a,b,c" into three integers.
void parseTriple(const std::string& text, int out[3]);

} // namespace dtf::app
