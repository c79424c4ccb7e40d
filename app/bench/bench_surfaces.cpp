// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench surfaces`: how fast the FA isosurface follows the threshold slider on an HCP-sized
// volume (145 x 174 x 145). The FA map is the real brain's resampled onto that grid when the shared data
// is there (realistic surface complexity), else the brain phantom's.
#include "app/bench/bench.h"
#include "app/command/args.h"
#include "app/command/options.h"
#include "io/model/error.h"
#include "io/phantoms.h"
#include "io/formats/tensor_io.h"
#include "surfaces/isosurface.h"
#include "io/formats/json.h"

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dtf::app {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Trilinear resampling of `src` onto a grid of `dims` covering the same world box.
ScalarVolume resample(const ScalarVolume& src, const glm::ivec3& dims) {
  glm::dmat4 scale(1.0);
  for (int a = 0; a < 3; ++a) scale[a][a] = static_cast<double>(src.grid.dims[a] - 1) / (dims[a] - 1);
  ScalarVolume out(Grid::fromAffine(dims, src.grid.voxelToWorld * scale), 1);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i)
        out.at(i, j, k) = sampleTrilinear(src, glm::dvec3(scale * glm::dvec4(i, j, k, 1.0)));
  return out;
}
} // namespace

const OptionTable& benchSurfacesOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench surfaces";
    t.intro =
        "Times FA isosurface re-extraction per threshold (0.20 .. 0.50) on a 145x174x145 FA volume,\n"
        "with the sweeper's one-off preparation (masking, 0.6-voxel smoothing, padding) reported apart.\n"
        "Goal: <= 50 ms per new threshold on 2 cores.";
    t.options = {
        O::flag("json", "one JSON object"),
        sharedDataOption(),
        O::integer("repeat", "N", 3, closedRange(1, 1000), "sweeps, the median is reported"),
    };
    return t;
  }();
  return table;
}

int benchSurfaces(const CommandArgs& argv) {
  ParsedOptions args(benchSurfacesOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const bool json = args.flag("json");
  auto dataArg = args.get("data");
  const int repeat = args.integer("repeat");
  args.finish();

  const glm::ivec3 hcp(145, 174, 145);
  std::string source;
  ScalarVolume fa;
  auto data = findSharedDataDir(dataArg);
  if (data && std::filesystem::exists(*data / "iu_prisma_dwi/derived/dti_FA.nii.gz")) {
    fa = resample(io::readScalarVolume((*data / "iu_prisma_dwi/derived/dti_FA.nii.gz").string()), hcp);
    source = "real brain FA (iu_prisma_dwi) resampled to 145x174x145";
  } else {
    io::PhantomOptions po;
    po.size = 160;
    fa = resample(computeFaMap(io::makePhantom("brain", po).tensors), hcp);
    source = "brain phantom FA resampled to 145x174x145 (no shared data found)";
  }

  surfaces::IsosurfaceOptions o;
  o.smoothSigmaVoxels = 0.6;
  o.minComponentFraction = 0.02;
  auto t0 = Clock::now();
  surfaces::IsosurfaceSweeper sweeper(fa, o);
  const double prepareMs = msSince(t0);

  std::vector<double> perThreshold;
  std::vector<std::pair<double, std::size_t>> rows;
  for (int r = 0; r < repeat; ++r)
    for (double t = 0.20; t <= 0.5001; t += 0.02) {
      auto t1 = Clock::now();
      Mesh m = sweeper.extract(t);
      perThreshold.push_back(msSince(t1));
      if (r == 0) rows.emplace_back(t, m.triangleCount());
    }
  const double med = median(perThreshold);
  double worst = 0;
  for (double v : perThreshold) worst = std::max(worst, v);

  if (json) {
    nlohmann::ordered_json thresholds = nlohmann::ordered_json::array();
    for (const auto& [fa, triangles] : rows)
      thresholds.push_back({{"fa", fa}, {"triangles", triangles}});
    const nlohmann::ordered_json j = {{"source", source},
                                      {"dims", {145, 174, 145}},
                                      {"prepare_ms", prepareMs},
                                      {"extract_ms_median", med},
                                      {"extract_ms_max", worst},
                                      {"goal_ms", 50},
                                      {"thresholds", thresholds}};
    std::printf("%s\n", io::jsonText(j).c_str());
  } else {
    std::printf("FA isosurface sweep on %s\n", source.c_str());
    std::printf("  one-off preparation (mask, smoothing, padding): %8.1f ms\n", prepareMs);
    std::printf("  per new threshold: median %.1f ms, max %.1f ms over %zu extractions (goal <= 50 ms)\n", med, worst,
                perThreshold.size());
    for (const auto& [t, n] : rows) std::printf("    FA %.2f: %8zu triangles\n", t, n);
  }
  return 0;
}

} // namespace dtf::app
