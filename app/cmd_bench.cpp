#include "app/bench.h"
#include "app/commands.h"

#include "io/model/error.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace dtf::app {

std::optional<std::filesystem::path> findSharedDataDir(const std::optional<std::string>& given) {
  namespace fs = std::filesystem;
  if (given) return fs::path(*given);
  if (const char* env = std::getenv("DTF_SHARED_DATA"); env && *env) return fs::path(env);
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path())
    if (fs::exists(p / "shared" / "data" / "iu_prisma_dwi")) return p / "shared" / "data";
  return std::nullopt;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

int cmdBench(const CommandArgs& args) {
  if (args.empty() || args[0] == "--help") {
    std::printf("usage: dtfabric bench io|render|surfaces|view [OPTIONS] [--json]\n"
                "  io      load time of an HCP-sized tensor volume, DWI fit times, FA-map time\n"
                "  render    per-pass GPU times and ms/frame of the fabric against plain Phong\n"
                "  surfaces  FA-threshold sweep: re-extraction time per threshold on an HCP-sized volume\n"
                "  tracts    streamlines/s of deterministic tensor tracking on the real brain\n"
                "  overlay   the tract overlay over the fabric (full, budgeted moving/still) and near-surface selection\n"
                "  check     the orientation check on the real DWI against MRtrix dwigradcheck (when on the PATH)\n"
                "  bids      seconds per participant of `dtfabric bids` on the real DWI; the group report for 300 rows\n");
    return args.empty() ? 1 : 0;
  }
  CommandArgs rest(args.begin() + 1, args.end());
  if (args[0] == "io") return benchIo(rest);
  if (args[0] == "render") return benchRender(rest);
  if (args[0] == "surfaces") return benchSurfaces(rest);
  if (args[0] == "view") return benchView(rest);
  if (args[0] == "tracts") return benchTracts(rest);
  if (args[0] == "overlay") return benchOverlay(rest);
  if (args[0] == "check") return benchCheck(rest);
  if (args[0] == "bids") return benchBids(rest);
  throw UsageError("unknown benchmark '" + args[0] + "' (io, render, surfaces, view)");
}

} // namespace dtf::app
