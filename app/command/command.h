// SPDX-License-Identifier: GPL-3.0-or-later
// What the command line and the benchmarks share: a command's arguments and its entry in a command list
// (name, help texts, entry point, option table). Each command returns the process exit code: 0 ok, 1 usage,
// 2 bad input, 3 GL/render failure; errors are thrown as dtf::Error subclasses and mapped to exit codes by
// the command line (app/cli/cli.cpp).
#pragma once

#include <string>
#include <vector>

namespace dtf::app {

using CommandArgs = std::vector<std::string>;
struct OptionTable; // app/command/options.h

struct Command {
  const char* name;
  const char* synopsis;    // the arguments after the name, as the reference's table shows them (nullptr: from
                           // the option table)
  const char* summary;     // one line for `dtfabric --help`
  const char* description; // the reference's command table and the man page
  int (*run)(const CommandArgs& args);
  const OptionTable& (*options)() = nullptr; // its flags, defaults, ranges and --help (nullptr: not yet)
};

} // namespace dtf::app
