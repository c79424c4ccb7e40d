// SPDX-License-Identifier: GPL-3.0-or-later
// The dtfabric subcommands. Each takes the arguments after its name and returns the process exit code
// (app/command/command.h).
//
// A new command is one entry in commands() (cli.cpp) and its file app/cli/cmd_NAME.cpp with
// `int cmdName(const CommandArgs&)` declared here; `dtfabric --help`, `dtfabric help --markdown` (the command
// tables of README.md and sample_data/guide/reference.md) and the test that checks them follow from the entry.
#pragma once

#include "app/command/command.h"
#include "app/command/options.h"
#include "surfaces/selection/regions.h"

#include <string>
#include <vector>

namespace dtf::app {

int cmdInfo(const CommandArgs& args);
int cmdFit(const CommandArgs& args);
int cmdPhantom(const CommandArgs& args);
int cmdSurface(const CommandArgs& args);
int cmdRender(const CommandArgs& args);
int cmdMovie(const CommandArgs& args);
int cmdBench(const CommandArgs& args);
int cmdView(const CommandArgs& args);
int cmdTrack(const CommandArgs& args);
int cmdCompare(const CommandArgs& args);
int cmdCheck(const CommandArgs& args);
int cmdConvert(const CommandArgs& args);
int cmdSelect(const CommandArgs& args);
int cmdProfile(const CommandArgs& args);
// `info` for tract files (cmdInfo hands over when FILE is a tractogram).
int cmdTractInfo(const CommandArgs& args);
int cmdHelp(const CommandArgs& args);
int cmdBids(const CommandArgs& args);
int cmdWeb(const CommandArgs& args);

// The option tables of the commands (app/command/options.h), each in its command's file.
const OptionTable& infoOptions();
const OptionTable& tractInfoOptions();
const OptionTable& fitOptions();
const OptionTable& phantomOptions();
const OptionTable& surfaceOptions();
const OptionTable& renderOptions();
const OptionTable& movieOptions();
const OptionTable& trackOptions();
const OptionTable& convertOptions();
const OptionTable& selectOptions();
const OptionTable& profileOptions();
const OptionTable& compareOptions();
const OptionTable& checkOptions();
const OptionTable& bidsOptions();
const OptionTable& webOptions();
const OptionTable& viewOptions();
const OptionTable& helpOptions();

// The region rows (--include, --exclude, --include-ordered) that `select` and `track` share, and the regions
// they give (ui/session/region_spec.h; InputError for a bad SPEC).
std::vector<CliOption> regionOptions();
std::vector<surfaces::Region> regionsFrom(ParsedOptions& args);

// All commands, in the order `dtfabric --help` lists them.
const std::vector<Command>& commands();
// A command's one-line summary (`dtfabric --help`, README.md's table), its arguments after the name (usage
// line, the reference's table) and its description (the reference's table, man page).
std::string summaryOf(const Command& c);
std::string synopsisOf(const Command& c);
std::string descriptionOf(const Command& c);
// The documentation's tables (markdown), blank-line separated: README.md's short command table (name, summary,
// where the whole help is), the reference's command table (synopsis, description) and the viewer's script
// commands (sample_data/guide/reference.md holds the last two).
std::string markdownTables();
// Entry point shared by main() and the CLI tests.
int runCli(int argc, char** argv);

} // namespace dtf::app
