// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/formats/json.h"
#include "io/model/error.h"
#include "surfaces/fibre_surface.h"
#include "surfaces/isosurface.h"
#include "surfaces/mesh_checks.h"
#include "surfaces/mesh_io.h"
#include "surfaces/slices.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace dtf::app {

namespace {
// The quality figure of the axis-aligned plane through a fibre surface's seed line (`from` names its axis;
// empty: the axis plane that best contains the line), and the plane's name.
double flatSliceScore(const session::SurfaceSpec& spec, const TensorField& field, const std::string& from,
                      std::string& name) {
  const glm::dvec3 a = spec.voxelCoords ? field.grid.toWorld(spec.a) : spec.a;
  const glm::dvec3 b = spec.voxelCoords ? field.grid.toWorld(spec.b) : spec.b;
  const glm::dvec3 dir = glm::normalize(b - a);
  int axis = 2; // world axis of the plane normal: 0 sagittal, 1 coronal, 2 axial
  if (!from.empty()) {
    axis = 2 - static_cast<int>(surfaces::parseSliceAxis(from)); // Axial=0 -> z, Coronal=1 -> y, Sagittal=2 -> x
  } else {
    for (int c : {1, 0})
      if (std::abs(dir[c]) < std::abs(dir[axis]) - 1e-9) axis = c;
  }
  glm::dvec3 n(0.0);
  n[axis] = 1;
  name = axis == 2 ? "axial" : axis == 1 ? "coronal" : "sagittal";
  ScalarVolume clip(field.grid, 1);
  for (std::size_t i = 0; i < field.valid.size(); ++i)
    clip.data[i] = field.valid[i] ? 1.0f : 0.0f;
  surfaces::SliceOptions so;
  so.clip = &clip;
  const Mesh flat = surfaces::makePlane(field.grid, 0.5 * (a + b), n, 0.5 * field.grid.spacing.x, so);
  return surfaces::fibreCrossingScore(flat, field);
}

double meshArea(const Mesh& m) {
  double a = 0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
    a += 0.5 * glm::length(glm::cross(m.positions[m.indices[t + 1]] - m.positions[m.indices[t]],
                                      m.positions[m.indices[t + 2]] - m.positions[m.indices[t]]));
  return a;
}
} // namespace

const OptionTable& surfaceOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const session::SurfaceBuildOptions bo;
    OptionTable t;
    t.command = "surface";
    t.positionals = "INPUT";
    t.maxPositionals = 1;
    t.synopsisTail = "SURFACE -o MESH.ply|.vtp|.obj [OPTIONS]";
    t.intro =
        "Extracts a surface from a tensor volume (or a DWI with --bval/--bvec), writes it as a mesh in world RAS mm\n"
        "and prints its quality figure: the FA- and area-weighted mean of |e1 . n|, how much of the principal\n"
        "fibre direction the fabric's projection onto the surface throws away (0 best, 1 worst).";
    t.options = {
        O::text("surface", "SPEC",
                "fa=T | iso=FILE:V | slice=AXIS[:I] | plane=X,Y,Z:NX,NY,NZ | fibre=X0,Y0,Z0:X1,Y1,Z1 | "
                "fibre-voxel=I0,J0,K0:I1,J1,K1 | mesh=FILE")
            .hidden()
            .under("SURFACE is one of"),
        O::text("fa", "T",
                "FA isosurface at T (same as --surface fa=T), smoothed as --mesh-smooth and --max-shift say")
            .hidden(),
        O::text("slice", "AXIS[:I]",
                "axial|coronal|sagittal slice I (default the middle), clipped to the data")
            .hidden(),
        O::text("fibre-surface", "X0,Y0,Z0:X1,Y1,Z1", "stream surface of e1 seeded on a line (world mm)")
            .hidden(),
        O::text("fibre-surface-voxel", "I0,J0,K0:I1,J1,K1", "the same in voxel indices").hidden(),
        O::text("output", "MESH", "the mesh to write: .ply, .vtp or .obj").hidden().under("Options"),
        layoutOption(LayoutNames::Tensor).hidden(),
        bvalOption().hidden(),
        bvecOption().hidden(),
        O::number("smooth", "SIGMA", bo.smoothSigmaVoxels, closedRange(0, surfaces::kMaxSmoothSigmaVoxels),
                  "FA isosurface pre-smoothing in voxels (0 = none)")
            .hidden(),
        O::integer("mesh-smooth", "N", bo.meshSmoothIterations, closedRange(0, 200),
                   "FA isosurfaces: windowed-sinc mesh smoothing iterations (VTK, pass band 0.1; 0 = none); "
                   "normals recomputed after")
            .hidden(),
        O::number("max-shift", "VOXELS", bo.maxShiftVoxels, atLeast(0),
                  "FA isosurfaces: the smoothing moves no vertex further than this (larger shifts clamped; "
                  "reported)")
            .hidden(),
        O::number("min-component", "F", bo.minComponentFraction, closedRange(0, 1),
                  "drop components smaller than F x the largest")
            .hidden(),
        O::number("step", "MM", bo.fibreStepMm, above(0), "fibre surfaces: tracing step").hidden(),
        O::number("length", "MM", bo.fibreLengthMm, above(0), "fibre surfaces: length of each traced line")
            .hidden(),
        O::number("fa-stop", "F", bo.fibreFaStop, closedRange(0, 1), "fibre surfaces: stop below this FA")
            .hidden(),
        O::number("seed-spacing", "MM", bo.fibreSeedSpacingMm, above(0),
                  "fibre surfaces: seed spacing on the line")
            .hidden(),
        O::text(
            "from", "AXIS",
            "fibre surfaces: the flat slice to compare with (default: the axis plane that best contains the "
            "seed line)")
            .hidden(),
        O::flag("check", "report self-intersections (CGAL); always done for fibre surfaces").hidden(),
        O::flag("repair", "remove self-intersecting triangles before writing").hidden(),
        O::number("remesh", "EDGE", 0, atLeast(0), "isotropic remeshing to EDGE mm (0 = none)").hidden(),
        O::flag("force", "overwrite an existing output").hidden(),
        O::flag("json", "print the report as one JSON object").hidden(),
    };
    return t;
  }();
  return table;
}

int cmdSurface(const CommandArgs& argv) {
  ParsedOptions args(surfaceOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string input = args.positional(0, "INPUT");
  const std::string output = args.required("output");
  const std::optional<std::string> given = surfaceArgument(args);
  if (!given) throw UsageError("give exactly one surface (--surface, --fa, --slice or --fibre-surface)");
  session::SurfaceSpec spec = session::parseSurfaceSpec(*given);
  session::TensorInputOptions in;
  in.layout = io::parseLayout(args.text("layout"));
  in.bval = args.text("bval");
  in.bvec = args.text("bvec");
  session::SurfaceBuildOptions bo;
  bo.smoothSigmaVoxels = args.number("smooth");
  bo.minComponentFraction = args.number("min-component");
  bo.meshSmoothIterations = args.integer("mesh-smooth");
  bo.maxShiftVoxels = args.number("max-shift");
  surfaces::SmoothingReport smoothing;
  bo.smoothing = &smoothing;
  bo.fibreStepMm = args.number("step");
  bo.fibreLengthMm = args.number("length");
  bo.fibreFaStop = args.number("fa-stop");
  bo.fibreSeedSpacingMm = args.number("seed-spacing");
  const std::string from = args.text("from");
  const bool json = args.flag("json"), force = args.flag("force"), repair = args.flag("repair");
  const bool check = args.flag("check") || repair || spec.kind == session::SurfaceSpec::Kind::Fibre;
  const double remesh = args.number("remesh");
  args.finish();

  io::refuseOverwritingInput(output, {input, spec.file, in.bval, in.bvec});
  if (!force && io::outputExists(output)) throw InputError(output + " exists (use --force to overwrite)");

  in.quiet = json;
  io::LoadedTensors loaded = session::loadTensorInput(input, in);
  const TensorField& field = loaded.field;
  ScalarVolume fa = computeFaMap(field);
  auto t0 = std::chrono::steady_clock::now();
  Mesh mesh;
  try {
    mesh = session::buildSurface(spec, field, fa, bo);
  } catch (const Error&) {
    rethrowWithContext("while building the " + session::describeSurface(spec) + " of " + input);
  }
  double buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (remesh > 0) mesh = surfaces::remeshIsotropic(mesh, remesh);
  std::size_t intersections = 0, removed = 0;
  bool checked = false;
  if (check) {
    intersections = surfaces::findSelfIntersections(mesh).intersectingPairs;
    checked = true;
    if (repair && intersections > 0) mesh = surfaces::removeSelfIntersections(mesh, &removed);
  }
  double scoreWeight = 0;
  const double score = surfaces::fibreCrossingScore(mesh, field, &scoreWeight);
  const bool scored = scoreWeight > 0; // no triangle in valid, anisotropic data: nothing was measured

  // Fibre surfaces are compared with the flat slice through their seed line.
  std::string flatName;
  const double flatScore =
      spec.kind == session::SurfaceSpec::Kind::Fibre ? flatSliceScore(spec, field, from, flatName) : -1;

  surfaces::writeMesh(output, mesh);

  if (json) {
    nlohmann::ordered_json j = {{"surface", session::describeSurface(spec)},
                                {"triangles", mesh.triangleCount()},
                                {"vertices", mesh.positions.size()},
                                {"area_mm2", meshArea(mesh)},
                                {"build_ms", buildMs},
                                {"e1_dot_n", scored ? nlohmann::ordered_json(score) : nullptr}};
    if (flatScore >= 0) {
      j["flat_slice"] = flatName;
      j["flat_e1_dot_n"] = flatScore;
    }
    if (checked) {
      j["self_intersections"] = intersections;
      j["removed_triangles"] = removed;
    }
    if (smoothing.vertices) {
      j["smoothing_max_shift_voxels"] = smoothing.maxShiftVoxels;
      j["smoothing_clamped"] = smoothing.clamped;
    }
    j["output"] = output;
    std::printf("%s\n", io::jsonText(j).c_str());
  } else {
    std::printf("surface:   %s\n", session::describeSurface(spec).c_str());
    std::printf("layout:    %s (%s)\n", io::layoutName(loaded.layout), loaded.layoutReason.c_str());
    std::printf("mesh:      %zu triangles, %zu vertices, %.1f mm^2, built in %.1f ms\n", mesh.triangleCount(),
                mesh.positions.size(), meshArea(mesh), buildMs);
    if (smoothing.vertices)
      std::printf("smoothing: %d windowed-sinc iterations, largest shift %.3f voxel, %zu of %zu vertices clamped "
                  "to %.2f voxel\n",
                  bo.meshSmoothIterations, smoothing.maxShiftVoxels, smoothing.clamped, smoothing.vertices,
                  bo.maxShiftVoxels);
    if (scored)
      std::printf("quality:   mean |e1 . n| = %.4f (FA- and area-weighted; 0 = fibres lie in the surface)\n",
                  score);
    else
      std::printf("quality:   not measured: no triangle lies in the data's valid tensors\n");
    if (flatScore >= 0)
      std::printf("           the flat %s plane through the seed line: %.4f\n", flatName.c_str(), flatScore);
    if (checked)
      std::printf("check:     %zu self-intersecting triangle pairs%s\n", intersections,
                  removed ? (", " + std::to_string(removed) + " triangles removed").c_str() : "");
    std::printf("wrote:     %s\n", output.c_str());
  }
  return 0;
}

} // namespace dtf::app
