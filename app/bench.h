// Benchmarks behind `dtfabric bench NAME`. Each prints a human-readable table, or one JSON object with
// --json, and returns the exit code.
#pragma once

#include "app/commands.h"

namespace dtf::app {

int benchIo(const CommandArgs& args);
int benchRender(const CommandArgs& args);

} // namespace dtf::app
