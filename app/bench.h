// Benchmarks behind `dtfabric bench NAME`. Each prints a human-readable table, or one JSON object with
// --json, and returns the exit code.
#pragma once

#include "app/commands.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

int benchIo(const CommandArgs& args);
int benchRender(const CommandArgs& args);
int benchSurfaces(const CommandArgs& args);
int benchView(const CommandArgs& args);
int benchTracts(const CommandArgs& args);
int benchOverlay(const CommandArgs& args);

// The shared real-data folder: `given`, else $DTF_SHARED_DATA, else a shared/data folder beside an ancestor
// of the executable (the checkout's ../shared/data). nullopt when none exists.
std::optional<std::filesystem::path> findSharedDataDir(const std::optional<std::string>& given);

// Median of a non-empty sample (the vector is reordered).
double median(std::vector<double> v);

} // namespace dtf::app
