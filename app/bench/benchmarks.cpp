// SPDX-License-Identifier: GPL-3.0-or-later
// The benchmark list of `dtfabric bench` and the helpers the benchmarks share.
#include "app/bench/bench.h"
#include "app/command/options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <sys/resource.h>
#include <unistd.h>

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

double loadAverage() {
  double l = -1;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &l) != 1) l = -1;
    std::fclose(f);
  }
  return l;
}

double childCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

CliOption sharedDataOption() {
  return CliOption::text(
      "data", "DIR",
      "the shared data folder (default $DTF_SHARED_DATA, else shared/data beside an ancestor of "
      "the executable)");
}

const std::vector<Benchmark>& benchmarks() {
  static const std::vector<Benchmark> list = {
      {"io",
       "load time of an HCP-sized tensor volume, DWI fit times, FA-map time, the real tensor in each format, "
       "tractogram loads (stroke.trk.gz beside nibabel, a 1 M-streamline TRX), a 200-resample wild bootstrap of "
       "the bundled brain",
       benchIo, benchIoOptions},
      {"render", "per-pass GPU times and ms/frame of the fabric against plain Phong", benchRender,
       benchRenderOptions},
      {"surfaces", "FA-threshold sweep: re-extraction time per threshold on an HCP-sized volume",
       benchSurfaces, benchSurfacesOptions},
      {"tracts", "streamlines/s of deterministic tensor tracking on the real brain", benchTracts,
       benchTractsOptions},
      {"select",
       "ROI selection at whole-brain scale: index build and sphere queries on 10 M synthetic streamlines, the "
       "real tracts, `select` against MRtrix tckedit on 1 M streamlines (when on the PATH)",
       benchSelect, benchSelectOptions},
      {"overlay",
       "the tract overlay over the fabric (full, budgeted moving/still) and near-surface selection",
       benchOverlay, benchOverlayOptions},
      {"view", "the viewer's frame times and FA-sweep latency, headless", benchView, benchViewOptions},
      {"check", "the orientation check on the real DWI against MRtrix dwigradcheck (when on the PATH)",
       benchCheck, benchCheckOptions},
      {"bids", "seconds per participant of `dtfabric bids` on the real DWI; the group report for 300 rows",
       benchBids, benchBidsOptions},
  };
  return list;
}

} // namespace dtf::app
