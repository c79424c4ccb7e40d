// The dtfabric subcommands. Each takes the arguments after its name and returns the process exit code:
// 0 ok, 1 usage, 2 bad input, 3 GL/render failure. Errors are thrown as dtf::Error subclasses and mapped
// to exit codes in cli.cpp.
#pragma once

#include <string>
#include <vector>

namespace dtf::app {

using CommandArgs = std::vector<std::string>;

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const CommandArgs& args);
};

int cmdInfo(const CommandArgs& args);
int cmdFit(const CommandArgs& args);
int cmdPhantom(const CommandArgs& args);
int cmdSurface(const CommandArgs& args);
int cmdRender(const CommandArgs& args);
int cmdBench(const CommandArgs& args);
int cmdView(const CommandArgs& args);
int cmdTrack(const CommandArgs& args);
int cmdCompare(const CommandArgs& args);
int cmdCheck(const CommandArgs& args);
int cmdBids(const CommandArgs& args);

// All commands, in the order `dtfabric --help` lists them.
const std::vector<Command>& commands();
// Entry point shared by main() and the CLI tests.
int runCli(int argc, char** argv);

} // namespace dtf::app
