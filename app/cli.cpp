#include "app/commands.h"

#include "io/model/error.h"
#include "io/model/log.h"

#include <cstdio>
#include <cstring>
#include <iostream>

namespace dtf::app {

const std::vector<Command>& commands() {
  static const std::vector<Command> list = {
      {"info", "describe a tensor, scalar or DWI volume (layout, orientation, ranges, one voxel)", cmdInfo},
      {"fit", "fit diffusion tensors to a DWI with bval/bvec (WLS or OLS)", cmdFit},
      {"phantom", "write an analytic tensor field (sphere, bretzel5, constant, crossing, brain)", cmdPhantom},
      {"surface", "extract an FA isosurface, slice or fibre-following surface to a mesh, with its quality", cmdSurface},
      {"render", "render the fabric on a surface to PNG, headless", cmdRender},
      {"track", "deterministic tensor tractography to .tck/.trk/.vtk", cmdTrack},
      {"compare", "angle between tracts and the fabric direction on a surface", cmdCompare},
      {"check", "orientation check: a flipped or permuted gradient table or tensor frame, and its fix", cmdCheck},
      {"bids", "BIDS App: per-run fit, orientation check and figures; group table and HTML report", cmdBids},
      {"view", "open the viewer (GLFW window with ImGui panels)", cmdView},
      {"bench", "benchmarks: io, render", cmdBench},
  };
  return list;
}

namespace {
void printUsage() {
  std::printf("usage: dtfabric COMMAND [ARGS]\n\ncommands:\n");
  for (const auto& c : commands()) std::printf("  %-9s %s\n", c.name, c.summary);
  std::printf("\n`dtfabric COMMAND --help` describes each command.\n"
              "Exit codes: 0 ok, 1 usage, 2 bad input, 3 GL/render failure.\n");
}
} // namespace

int runCli(int argc, char** argv) {
  setLogSink([](LogLevel level, const std::string& msg) {
    if (level == LogLevel::Debug) return;
    const char* tag = level == LogLevel::Warning ? "warning: " : level == LogLevel::Error ? "error: " : "";
    std::cerr << tag << msg << "\n";
  });
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    printUsage();
    return argc < 2 ? 1 : 0;
  }
  std::string name = argv[1];
  CommandArgs rest(argv + 2, argv + argc);
  for (const auto& c : commands()) {
    if (name != c.name) continue;
    try {
      return c.run(rest);
    } catch (const UsageError& e) {
      std::cerr << "dtfabric " << name << ": " << e.what() << "\n(see `dtfabric " << name << " --help`)\n";
      return 1;
    } catch (const GlError& e) {
      std::cerr << "dtfabric " << name << ": GL error: " << e.what() << "\n";
      return 3;
    } catch (const Error& e) {
      std::cerr << "dtfabric " << name << ": " << e.what() << "\n";
      return 2;
    } catch (const std::bad_alloc&) {
      std::cerr << "dtfabric " << name << ": out of memory\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "dtfabric " << name << ": unexpected error: " << e.what() << "\n";
      return 2;
    }
  }
  std::cerr << "dtfabric: unknown command '" << name << "'\n";
  printUsage();
  return 1;
}

} // namespace dtf::app
