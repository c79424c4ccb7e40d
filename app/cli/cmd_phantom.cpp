// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric phantom`: writes an analytic tensor field (io/phantoms.h) in a chosen on-disk layout, and
// optionally its scalar field, so every later stage can be run on input with a known answer.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/phantoms.h"

#include <cstdio>
#include <filesystem>

namespace dtf::app {

const OptionTable& phantomOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const io::PhantomOptions d;
    OptionTable t;
    t.command = "phantom";
    t.positionals = "NAME";
    t.maxPositionals = 1;
    t.intro =
        "Writes an analytic tensor field as NIfTI (.nii or .nii.gz; --layout applies), an MRtrix image (.mif,\n"
        ".mif.gz: MRtrix's convention) or NRRD (.nrrd). NAME is one of:\n"
        "  sphere    Hessian of the distance from the grid centre (curvature tensors, 1/mm)\n"
        "  bretzel5  Hessian of the Bretzel5 implicit function (paper Eq. 14; curvature tensors)\n"
        "  constant  one prolate tensor, eigenvalues (1.7, 0.3, 0.3)e-3 mm^2/s, everywhere\n"
        "  crossing  two prolate bundles crossing in the axial plane\n"
        "  brain     a small brain-like phantom: corpus callosum (left-right), corticospinal tracts\n"
        "            (superior-inferior) and cingula (anterior-posterior) in isotropic tissue and CSF\n"
        "The grid is RAS, centred at the world origin.";
    t.options = {
        O::text("output", "FILE", "tensor volume to write (a folder for --layout bedpostx)").required(),
        O::text("layout", "L",
                "fsl, mrtrix, symmatrix or dtitk; or a fibre-set layout (crossing and constant only): "
                "mrtrix-peaks, dipy-peaks (FILE) or bedpostx (FILE is a folder)",
                "fsl"),
        O::choice("grid", "G", {"ras", "las"}, "ras",
                  "ras, or las (x index towards the patient's left, det(affine) < 0)"),
        O::integer("size", "N", d.size, closedRange(4, 512),
                   "voxels per side (bretzel5 uses fewer slices in z)")
            .hidden(),
        O::number("spacing", "MM", d.spacing, closedRange(io::kMinPhantomSpacingMm, io::kMaxPhantomSpacingMm),
                  "voxel size in mm")
            .hidden(),
        O::number("angle", "DEG", d.angleDeg, anyNumber(), "constant: direction from +x towards +y").hidden(),
        O::number("elevation", "DEG", d.elevationDeg, anyNumber(),
                  "constant: direction out of the axial plane towards +z")
            .hidden(),
        O::number("crossing", "DEG", d.crossingDeg, anyNumber(), "crossing: angle between the bundles"),
        O::text("scalar", "FILE", "also write the scalar field (sphere: distance, bretzel5: f, others: FA)")
            .hidden(),
        O::flag("nifti2", "write NIfTI-2 instead of NIfTI-1").hidden(),
        O::flag("force", "overwrite existing output files").hidden(),
    };
    return t;
  }();
  return table;
}

int cmdPhantom(const CommandArgs& argv) {
  ParsedOptions args(phantomOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string name = args.positional(0, "phantom NAME (see --help)");
  auto output = std::optional<std::string>(args.required("output"));
  const std::string layoutName = args.text("layout");
  const bool fibres = io::isFibreLayoutName(layoutName);
  io::TensorLayout layout = fibres ? io::TensorLayout::Fsl : io::parseLayout(layoutName);
  if (fibres && layoutName == "fibres-auto") throw UsageError("--layout fibres-auto cannot be written");
  if (!fibres && layout == io::TensorLayout::Auto)
    throw UsageError("--layout auto cannot be written; choose fsl, mrtrix, symmatrix or dtitk");
  io::PhantomOptions o;
  o.size = args.integer("size");
  o.spacing = args.number("spacing");
  o.angleDeg = args.number("angle");
  o.elevationDeg = args.number("elevation");
  o.crossingDeg = args.number("crossing");
  o.las = args.text("grid") == "las";
  auto scalarPath = args.get("scalar");
  int version = args.flag("nifti2") ? 2 : 1;
  const bool force = args.flag("force");
  args.finish();
  io::refuseSameOutputs({*output, scalarPath ? *scalarPath : std::string()});
  for (const auto* out : {&*output, scalarPath ? &*scalarPath : nullptr}) {
    if (!out) continue;
    if (!fibres || layoutName != "bedpostx") io::refuseUnwritableOutput(*out);
    if (!force && io::outputExists(*out)) throw InputError(*out + " exists (use --force to overwrite it)");
  }

  if (fibres) {
    if (scalarPath) throw UsageError("--scalar is for tensor phantoms");
    FibreSet f = io::makeFibrePhantom(name, o);
    io::writeFibres(*output, f, io::parseFibreLayout(layoutName), version);
    const glm::ivec3 d = f.grid.dims;
    std::printf("wrote %s fibre phantom, %dx%dx%d voxels of %g mm (%s), %zu voxels with fibres, layout %s: %s\n",
                name.c_str(), d.x, d.y, d.z, o.spacing, f.grid.orientationCode().c_str(), f.occupiedVoxels(),
                layoutName.c_str(), output->c_str());
    return 0;
  }
  io::Phantom p = io::makePhantom(name, o);
  io::OutputBatch batch; // the tensors and the scalar field together, or neither
  io::writeTensorVolume(*output, p.tensors, layout, version);
  if (scalarPath) io::writeScalarVolume(*scalarPath, p.scalar, version);
  batch.commit();
  std::size_t valid = 0;
  for (unsigned char v : p.tensors.valid)
    valid += v;
  const glm::ivec3 d = p.tensors.grid.dims;
  std::printf("wrote %s phantom, %dx%dx%d voxels of %g mm, %zu valid, layout %s: %s\n", name.c_str(), d.x,
              d.y, d.z, o.spacing, valid, io::layoutName(layout), output->c_str());
  if (scalarPath) {
    std::printf("wrote scalar field (isovalue %g): %s\n", p.isovalue, scalarPath->c_str());
  }
  return 0;
}

} // namespace dtf::app
