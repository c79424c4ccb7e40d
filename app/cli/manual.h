// SPDX-License-Identifier: GPL-3.0-or-later
// The man pages and the bash completion, generated from commands() and the option tables (as the
// documentation's tables are), so they cannot drift from the parser. The build writes them with the hidden
// `dtfabric help --man NAME`, `--man-pages` and `--bash-completion` (cmake/DtfManual.cmake).
#pragma once

#include <string>
#include <vector>

namespace dtf::app {

// "dtfabric", then "dtfabric-COMMAND" for every command, in the order `dtfabric --help` lists them.
std::vector<std::string> manPageNames();
// The roff source of section-1 page `name` (one of manPageNames()); UsageError for another name.
std::string manPage(const std::string& name);
// A bash completion script defining _dtfabric: commands, benchmarks, each command's flags, a Choice
// option's values, file names for other values and positionals.
std::string bashCompletion();

} // namespace dtf::app
