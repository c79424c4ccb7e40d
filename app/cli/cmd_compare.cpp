// `dtfabric compare`: does the fabric on a surface point where the tracts go? (surfaces/agreement.h)
#include "app/cli/args.h"
#include "app/cli/commands.h"
#include "app/scene/surface_spec.h"
#include "app/scene/tensor_input.h"
#include "app/scene/tract_files.h"
#include "io/model/error.h"
#include "surfaces/agreement.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace dtf::app {

namespace {
const char* kHelp = R"(usage: dtfabric compare INPUT --tracts FILE --surface SPEC [OPTIONS]

Compares the fabric's direction on a surface with tractography. For each tract point within --near mm of
the surface: the angle (0-90 deg) between the tract tangent projected onto the surface (at the closest
point, triangle normal n) and the fabric's principal direction there, the principal eigenvector of the
projected tensor T' = P T P^T, P = I - n n^T (tensor interpolated at the closest point). Points where the
tract crosses the surface steeply (projected tangent < 0.25 of its length) or T' has no preferred
direction (in-plane eigenvalues within 2% of each other, or no data) are skipped and counted.

  --tracts FILE         .tck, .trk or .vtk tracts (world RAS mm)
  --surface SPEC        fa=T | iso=FILE:V | slice=AXIS[:I] | plane=X,Y,Z:NX,NY,NZ | fibre=... | mesh=FILE
  --near MM             distance from the surface (default 2)
  --bins N              histogram bins over 0..90 deg (default 9)
  --layout L            tensor layout override (fsl, mrtrix, symmatrix, dtitk)
  --bval F --bvec F     treat INPUT as a DWI and fit tensors
  --json                {points, mean_deg, median_deg, frac_below_15, histogram: [...], bin_deg, ...}
)";
} // namespace

int cmdCompare(const CommandArgs& argv) {
  Args args(argv, {"json", "help"});
  if (args.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::string input = args.positional(0, "INPUT");
  const std::string tractsPath = args.getOr("tracts", "");
  const std::string surfaceText = args.getOr("surface", "");
  if (tractsPath.empty()) throw UsageError("missing --tracts FILE");
  if (surfaceText.empty()) throw UsageError("missing --surface SPEC");
  surfaces::AgreementOptions ao;
  ao.nearMm = args.getDouble("near", ao.nearMm);
  ao.bins = args.getInt("bins", ao.bins);
  if (!(ao.nearMm >= 0)) throw UsageError("--near must be >= 0");
  if (ao.bins < 1 || ao.bins > 90) throw UsageError("--bins must be 1..90");
  TensorInputOptions in;
  in.layout = io::parseLayout(args.getOr("layout", "auto"));
  in.bval = args.getOr("bval", "");
  in.bvec = args.getOr("bvec", "");
  const bool json = args.flag("json");
  args.finish();
  const SurfaceSpec spec = parseSurfaceSpec(surfaceText);

  const Polylines tracts = readTracts(tractsPath);
  in.quiet = json;
  io::LoadedTensors loaded = loadTensorInput(input, in);
  const TensorField& field = loaded.field;
  Mesh mesh;
  try {
    mesh = buildSurface(spec, field, computeFaMap(field));
  } catch (const Error&) {
    rethrowWithContext("while building the " + describeSurface(spec) + " of " + input);
  }
  const surfaces::AgreementResult r = surfaces::tractSurfaceAgreement(tracts, mesh, field, ao);

  if (json) {
    std::printf("{\"points\": %zu, \"mean_deg\": %.4f, \"median_deg\": %.4f, \"frac_below_15\": %.6f, "
                "\"histogram\": [",
                r.anglesDeg.size(), r.meanDeg, r.medianDeg, r.fracBelow15);
    for (std::size_t b = 0; b < r.histogram.size(); ++b)
      std::printf("%s%zu", b ? ", " : "", r.histogram[b]);
    std::printf(
        "], \"bin_deg\": %g, \"near_points\": %zu, \"skipped_tangent\": %zu, \"skipped_degenerate\": %zu, "
        "\"streamlines\": %zu, \"near_mm\": %g, \"surface\": \"%s\"}\n",
        r.binDeg, r.nearPoints, r.skippedTangent, r.skippedDegenerate, tracts.lineCount(), ao.nearMm,
        describeSurface(spec).c_str());
    return 0;
  }
  std::printf("tracts: %s (%zu streamlines, %zu points)\n", tractsPath.c_str(), tracts.lineCount(),
              tracts.points.size());
  std::printf("surface: %s (%zu triangles)\n", describeSurface(spec).c_str(), mesh.triangleCount());
  std::printf(
      "points within %g mm: %zu; compared %zu (skipped: %zu steep crossings, %zu without an in-surface "
      "direction)\n",
      ao.nearMm, r.nearPoints, r.anglesDeg.size(), r.skippedTangent, r.skippedDegenerate);
  if (r.anglesDeg.empty()) {
    std::printf("no tract point could be compared\n");
    return 0;
  }
  std::printf("angle between tract and fabric: mean %.1f deg, median %.1f deg, %.1f%% below 15 deg\n",
              r.meanDeg, r.medianDeg, 100.0 * r.fracBelow15);
  const std::size_t peak = *std::max_element(r.histogram.begin(), r.histogram.end());
  for (std::size_t b = 0; b < r.histogram.size(); ++b) {
    const int width =
        peak ? static_cast<int>(50.0 * static_cast<double>(r.histogram[b]) / static_cast<double>(peak) + 0.5)
             : 0;
    std::printf("  %5.1f-%5.1f deg %8zu %s\n", b * r.binDeg, (b + 1) * r.binDeg, r.histogram[b],
                std::string(static_cast<std::size_t>(width), '#').c_str());
  }
  return 0;
}

} // namespace dtf::app
