#include "app/bench.h"
#include "app/commands.h"

#include "io/model/error.h"

#include <cstdio>

namespace dtf::app {

int cmdBench(const CommandArgs& args) {
  if (args.empty() || args[0] == "--help") {
    std::printf("usage: dtfabric bench io|render [OPTIONS] [--json]\n"
                "  io      load time of an HCP-sized tensor volume, DWI fit times, FA-map time\n"
                "  render  per-pass GPU times and ms/frame of the fabric against plain Phong\n");
    return args.empty() ? 1 : 0;
  }
  CommandArgs rest(args.begin() + 1, args.end());
  if (args[0] == "io") return benchIo(rest);
  if (args[0] == "render") return benchRender(rest);
  throw UsageError("unknown benchmark '" + args[0] + "' (io, render)");
}

} // namespace dtf::app
