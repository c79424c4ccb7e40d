// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmarks behind `dtfabric bench NAME`. Each prints a human-readable table, or one JSON object with
// --json, and returns the exit code.
#pragma once

#include "app/command/command.h"
#include "app/command/options.h"
#include "io/model/geometry.h"
#include "io/model/tensor_field.h"

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dtf::app {

// One benchmark of `dtfabric bench NAME`. A new benchmark is one entry in benchmarks()
// (app/bench/benchmarks.cpp) and its file app/bench/bench_NAME.cpp; `dtfabric --help`, `bench --help` and the
// command tables of the README and the reference follow.
struct Benchmark {
  const char* name;
  const char* summary; // one line
  int (*run)(const CommandArgs& args);
  const OptionTable& (*options)() = nullptr; // its flags and --help (app/command/options.h; nullptr: not yet)
};
// Every benchmark, in the order help lists them.
const std::vector<Benchmark>& benchmarks();

int benchIo(const CommandArgs& args);
int benchRender(const CommandArgs& args);
int benchSurfaces(const CommandArgs& args);
int benchView(const CommandArgs& args);
int benchTracts(const CommandArgs& args);
int benchOverlay(const CommandArgs& args);
int benchCheck(const CommandArgs& args);
int benchBids(const CommandArgs& args);
int benchSelect(const CommandArgs& args);
// Their option tables, each in its benchmark's file.
const OptionTable& benchIoOptions();
const OptionTable& benchRenderOptions();
const OptionTable& benchSurfacesOptions();
const OptionTable& benchTractsOptions();
const OptionTable& benchOverlayOptions();
const OptionTable& benchViewOptions();
const OptionTable& benchCheckOptions();
const OptionTable& benchBidsOptions();
const OptionTable& benchSelectOptions();

// The `--data DIR` row every benchmark that reads the shared data has.
CliOption sharedDataOption();

// The shared real-data folder: `given`, else $DTF_SHARED_DATA, else a shared/data folder beside an ancestor
// of the executable (the checkout's ../shared/data). nullopt when none exists.
std::optional<std::filesystem::path> findSharedDataDir(const std::optional<std::string>& given);

// Tractogram load times for `bench io` (app/bench/bench_io_tracts.cpp): stroke.trk.gz from the shared data beside
// nibabel's load of the same file in the same run (when python3 with nibabel is present), and a TRX of 1 M
// streamlines made here. Seconds; < 0 when not measured (a note says why).
struct TractLoadFigure {
  std::string key, label, goalText;
  double wall = -1, cpu = -1, goal = -1;
};
std::vector<TractLoadFigure> benchTractLoads(const std::optional<std::filesystem::path>& dataDir,
                                             std::vector<std::string>& notes);
// Load time of the real tensor through each tensor format (app/bench/bench_io_formats.cpp); empty (with a note)
// when the shared data are missing.
struct FormatLoadFigure {
  std::string key, label;
  double wall = -1, cpu = -1; // median seconds
};
std::vector<FormatLoadFigure> benchFormatLoads(const std::optional<std::filesystem::path>& dataDir,
                                               std::vector<std::string>& notes);
// The 1-minute load average, to tell figures taken on a contended machine apart (-1 when unknown).
double loadAverage();

// CPU seconds (user + system) of this process's finished children so far: a peer's CPU time is the
// difference around its run.
double childCpuSeconds();

// Median of a non-empty sample (the vector is reordered).
double median(std::vector<double> v);

// The peer of `bench render` (app/bench/bench_render_peer.cpp): ParaView's Surface LIC, run through pvbatch
// (Debian package paraview) on the same mesh with one vector per vertex, the principal in-surface
// eigenvector of the same tensor field, at the same size and coverage, the camera turning a little each
// frame.
struct RenderPeerOptions {
  int width = 1024, height = 768; // pixels
  int frames = 10;                // timed frames per mode, after one warm-up frame
  std::string pngPath;            // where to save one frame of the default LIC; empty: none
};
struct RenderPeerResult {
  bool ran = false;
  std::string name; // e.g. "ParaView 5.11.0 Surface LIC"
  std::string note; // why there are no figures (absent, no display, failed), empty when ran
  double licDefaultMs = 0, licOneStepMs = 0, surfaceMs = 0; // wall-clock ms/frame
  // pvbatch's CPU time per frame, all its threads (llvmpipe's included; not Xvfb's): less sensitive to
  // other processes' load than the wall clock. -1 when not reported.
  double licDefaultCpuMs = -1, licOneStepCpuMs = -1, surfaceCpuMs = -1;
  double coverage = 0; // fraction of pixels covered by the surface
  int licDefaultSteps = 0, frames = 0;
  std::string pixels; // the size ParaView rendered at, "WxH"
  std::string png;    // the saved frame, when asked for and written
};
// Runs the peer when pvbatch (or pvpython) is on the PATH and an X display is set or xvfb-run can provide
// one; $DTF_PARAVIEW_PYTHONPATH is prepended to its PYTHONPATH (for an unpacked python3-paraview). Never
// throws for a missing or failing peer: the result's note says what happened.
RenderPeerResult runRenderPeer(const Mesh& mesh, const TensorField& field, const RenderPeerOptions& options);
// The generated pvbatch script that reads `meshPath` (legacy VTK with point vectors "v") and prints
// "DTF_PEER key value" lines.
std::string renderPeerScript(const std::string& meshPath, const RenderPeerOptions& options);
// Reads the script's output; ran is true when all three timings are there.
RenderPeerResult parseRenderPeerOutput(const std::string& text);
// The unit eigenvector of the larger eigenvalue of T projected onto the plane with unit normal n
// (T' = P T P, P = I - n n^T), in world coordinates; any in-plane unit vector where they are equal.
glm::dvec3 principalInSurfaceDirection(const glm::dmat3& t, const glm::dvec3& n);
// Our figures on the same mesh, ms/frame (0 when not measured), for the ratios.
struct RenderPeerOurs {
  double fabricMs = 0, movingMs = 0, phongMs = 0, fabricCpuMs = 0, phongCpuMs = 0, movingCpuMs = 0;
};
// The peer's lines for the `bench render` table, and the "peer" (and "peer_note") members of its JSON object.
void printRenderPeerTable(const RenderPeerResult& peer, const RenderPeerOurs& ours);
void addRenderPeerJson(nlohmann::ordered_json& j, const RenderPeerResult& peer, const RenderPeerOurs& ours);

} // namespace dtf::app
