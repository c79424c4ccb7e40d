// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench NAME`: runs one benchmark of the list (app/bench/benchmarks.cpp).
#include "app/bench/bench.h"
#include "app/cli/commands.h"
#include "io/model/error.h"

#include <cstdio>

namespace dtf::app {

int cmdBench(const CommandArgs& args) {
  std::string names;
  for (const auto& b : benchmarks())
    names += (names.empty() ? "" : "|") + std::string(b.name);
  if (args.empty() || args[0] == "--help") {
    std::printf("usage: dtfabric bench %s [OPTIONS] [--json]\n", names.c_str());
    for (const auto& b : benchmarks())
      std::printf("  %-9s %s\n", b.name, b.summary);
    return args.empty() ? 1 : 0;
  }
  CommandArgs rest(args.begin() + 1, args.end());
  for (const auto& b : benchmarks())
    if (args[0] == b.name) return b.run(rest);
  throw UsageError("unknown benchmark '" + args[0] + "' (" + names + ")");
}

} // namespace dtf::app
