// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric compare`: does the fabric on a surface point where the tracts go? (surfaces/analyses/agreement.h)
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "surfaces/analyses/agreement.h"
#include "ui/session/fibre_input.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace dtf::app {

namespace {

struct Measured {
  Mesh mesh;
  surfaces::AgreementResult result;
  bool fibres = false; // against a fibre set's nearest population
};

Mesh surfaceOf(const session::SurfaceSpec& spec, const TensorField& field, const ScalarVolume& fa,
               const std::string& input) {
  try {
    session::SurfaceBuildOptions shown; // the surface as render and the viewer show it
    shown.dataEdgeCells = true;
    return session::buildSurface(spec, field, fa, shown);
  } catch (const Error&) {
    rethrowWithContext("while building the " + session::describeSurface(spec) + " of " + input);
  }
  return {};
}

Measured measureAgainstTensors(const io::OpenedInput& input, const std::string& layoutText,
                               const std::string& tensorPath, session::TensorInputOptions in,
                               const session::SurfaceSpec& spec, const Polylines& tracts,
                               const surfaces::AgreementOptions& ao) {
  if (!tensorPath.empty())
    throw UsageError("--tensor pairs a tensor with a fibre-set INPUT; " + input.path + " is not one");
  in.layout = io::parseLayout(layoutText);
  const io::LoadedTensors loaded = session::loadTensors(input, in);
  Measured m;
  m.mesh = surfaceOf(spec, loaded.field, computeFaMap(loaded.field), input.path);
  m.result = surfaces::tractSurfaceAgreement(tracts, m.mesh, loaded.field, ao);
  return m;
}

// The surface from the paired tensor (or the fibre set's carrier and own FA), the angles against the fibres.
Measured measureAgainstFibres(const io::OpenedInput& input, const std::string& tensorPath,
                              const session::SurfaceSpec& spec, const Polylines& tracts,
                              const surfaces::AgreementOptions& ao, bool quiet) {
  const session::FibreInput fi = session::loadFibreInput(input, tensorPath, quiet);
  session::checkFibreSurface(spec, fi);
  const ScalarVolume fa = fi.fa.data.empty() ? ScalarVolume(fi.carrier.grid, 1) : fi.fa;
  Measured m;
  m.fibres = true;
  m.mesh = surfaceOf(spec, fi.carrier, fa, input.path);
  m.result = surfaces::tractSurfaceAgreement(tracts, m.mesh, fi.fibres.set, ao);
  return m;
}

} // namespace

const OptionTable& compareOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const surfaces::AgreementOptions ao;
    OptionTable t;
    t.command = "compare";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.intro =
        "Compares the fabric's direction on a surface with tractography. For each tract point within --near mm of\n"
        "the surface: the angle (0-90 deg) between the tract tangent projected onto the surface (at the closest\n"
        "point, triangle normal n) and the fabric's principal direction there, the principal eigenvector of the\n"
        "projected tensor T' = P T P^T, P = I - n n^T (tensor interpolated at the closest point). Points where the\n"
        "tract crosses the surface steeply (projected tangent < 0.25 of its length) or T' has no preferred\n"
        "direction (in-plane eigenvalues within 2% of each other, or no data) are skipped and counted.\n"
        "\n"
        "INPUT may be a fibre set (MRtrix sh2peaks or DIPY peaks file, FSL bedpostx folder or dyadsN file, DSI\n"
        "Studio .fib.gz: as for `dtfabric render`). Each tract point is then measured against the NEAREST fibre\n"
        "population at the closest point (fibres interpolated as the renderer does, populations below\n"
        "--fibre-threshold x their voxel's strongest dropped, each projected onto the surface; those leaving the\n"
        "surface within ~14.5 deg of its normal skipped): a tract along either bundle of a crossing agrees with\n"
        "the fibre set, where the tensor's principal direction is the average of the bundles.";
    t.options = {
        O::text("tracts", "FILE", ".tck, .trk, .trk.gz, .trx, .vtk or .vtp tracts (world RAS mm)").required(),
        O::text("surface", "SPEC",
                "fa=T | iso=FILE:V | slice=AXIS[:I] | plane=X,Y,Z:NX,NY,NZ | fibre=... | mesh=FILE")
            .required(),
        O::number("near", "MM", ao.nearMm, atLeast(0), "distance from the surface"),
        O::integer("bins", "N", ao.bins, closedRange(1, 90), "histogram bins over 0..90 deg"),
        layoutOption(LayoutNames::TensorOrFibre).hidden(),
        pairedTensorOption("the surface's FA (fa= surfaces) and fibre= surfaces").hidden(),
        O::number(
            "fibre-threshold", "T", ao.fibreThreshold, closedRange(0, 0.999),
            "fibre sets: drop populations below T x their voxel's strongest (as `render --fibre-threshold`)")
            .hidden(),
        bvalOption().hidden(),
        bvecOption().hidden(),
        O::flag("json", "{points, mean_deg, median_deg, frac_below_15, histogram: [...], bin_deg, ...}"),
    };
    return t;
  }();
  return table;
}

int cmdCompare(const CommandArgs& argv) {
  ParsedOptions args(compareOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string input = args.positional(0, "INPUT");
  const std::string tractsPath = args.required("tracts");
  const std::string surfaceText = args.required("surface");
  surfaces::AgreementOptions ao;
  ao.nearMm = args.number("near");
  ao.bins = args.integer("bins");
  ao.fibreThreshold = static_cast<float>(args.number("fibre-threshold"));
  const std::string layoutText = args.text("layout");
  const std::string tensorPath = args.text("tensor");
  session::TensorInputOptions in;
  in.bval = args.text("bval");
  in.bvec = args.text("bvec");
  const bool json = args.flag("json");
  args.finish();
  const session::SurfaceSpec spec = session::parseSurfaceSpec(surfaceText);
  in.quiet = json;

  const Polylines tracts = session::readTracts(tractsPath);
  const io::OpenedInput opened =
      io::openInput(session::inputRequest(input, layoutText, in, in.bval.empty() && in.bvec.empty()));
  const bool fibres = opened.kind == io::InputKind::Fibres;
  if (fibres && !json && layoutText == "auto") logInfo(input + ": read as a fibre set (" + opened.reason + ")");
  const Measured m = fibres ? measureAgainstFibres(opened, tensorPath, spec, tracts, ao, json)
                            : measureAgainstTensors(opened, layoutText, tensorPath, in, spec, tracts, ao);
  const surfaces::AgreementResult& r = m.result;
  const Mesh& mesh = m.mesh;

  if (json) {
    const nlohmann::ordered_json j = {
        {"points", r.anglesDeg.size()},
        {"mean_deg", r.meanDeg}, // NaN, written as null, when no point was compared
        {"median_deg", r.medianDeg},
        {"frac_below_15", r.fracBelow15},
        {"histogram", r.histogram},
        {"bin_deg", r.binDeg},
        {"near_points", r.nearPoints},
        {"skipped_tangent", r.skippedTangent},
        {"skipped_degenerate", r.skippedDegenerate},
        {"streamlines", tracts.lineCount()},
        {"near_mm", ao.nearMm},
        {"surface", session::describeSurface(spec)},
        {"against", m.fibres ? "nearest fibre population" : "tensor principal direction"}};
    std::printf("%s\n", io::jsonText(j).c_str());
    return 0;
  }
  std::printf("tracts: %s (%zu streamlines, %zu points)\n", tractsPath.c_str(), tracts.lineCount(),
              tracts.points.size());
  std::printf("surface: %s (%zu triangles)\n", session::describeSurface(spec).c_str(), mesh.triangleCount());
  std::printf(
      "points within %g mm: %zu; compared %zu (skipped: %zu steep crossings, %zu without an in-surface "
      "direction)\n",
      ao.nearMm, r.nearPoints, r.anglesDeg.size(), r.skippedTangent, r.skippedDegenerate);
  if (r.anglesDeg.empty()) {
    std::printf("no tract point could be compared\n");
    return 0;
  }
  std::printf("against: %s\n", m.fibres ? "the nearest fibre population" : "the tensor's principal direction");
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
