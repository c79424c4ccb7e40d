// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric fit`: DWI + bval/bvec -> tensor volume on disk, through io/diffusion/dwi.h and io/formats/tensor_io.h.
#include "app/cli/commands.h"
#include "app/command/options.h"
#include "io/formats/atomic_file.h"
#include "io/diffusion/dwi.h"
#include "io/formats/formats.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "io/diffusion/uncertainty.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <unistd.h>

namespace dtf::app {

namespace {

// DWI path with its NIfTI extension replaced by `ext`, if that file exists.
std::optional<std::string> sibling(const std::string& dwi, const std::string& ext) {
  std::string base = dwi;
  for (const char* e : {".nii.gz", ".nii", ".mif.gz", ".mif", ".mih"}) {
    const std::string s(e);
    if (base.size() > s.size() && base.compare(base.size() - s.size(), s.size(), s) == 0) {
      base.resize(base.size() - s.size());
      break;
    }
  }
  std::string candidate = base + ext;
  if (candidate != dwi && std::filesystem::exists(candidate)) return candidate;
  return std::nullopt;
}

// Progress on stderr: one \r-updated percentage on a terminal, otherwise a line every 25%.
struct ProgressPrinter {
  bool tty = isatty(STDERR_FILENO) == 1;
  int lastShown = -1;
  const char* label = "fitting";
  void operator()(double f) {
    const int pct = static_cast<int>(std::lround(f * 100));
    if (tty) {
      if (pct == lastShown) return;
      std::fprintf(stderr, "\r%s: %3d%%", label, pct);
      if (pct >= 100) std::fputc('\n', stderr);
    } else {
      const int step = pct / 25 * 25;
      if (step == lastShown || step == 0) return;
      std::fprintf(stderr, "%s: %d%%\n", label, step);
      lastShown = step;
      return;
    }
    lastShown = pct;
    std::fflush(stderr);
  }
};

} // namespace

const OptionTable& fitOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    const io::FitOptions defaults;
    OptionTable t;
    t.command = "fit";
    t.positionals = "DWI";
    t.maxPositionals = 1;
    t.intro = "Fits a diffusion tensor per voxel (log-linear model; WLS = DIPY's two-step weighted fit).";
    t.options = {
        bvalOption().alsoSays(
            "; bvec 3xN or Nx3. Default: the DWI path with .nii/.nii.gz replaced by "
            ".bval/.bvec; not needed for an MRtrix DWI with a dw_scheme or a DSI Studio .src.gz "
            "(their own tables are used)"),
        bvecOption(),
        fitMaskOption().alsoSays("; default: an automatic, approximate mask (Otsu on the mean b=0 image)"),
        O::text(
            "output", "OUT",
            "output tensor volume, mm^2/s: .nii[.gz], .mif/.mif.gz (MRtrix image in MRtrix's convention), "
            ".mih or .nrrd (teem tensor NRRD in RAS space)")
            .required(),
        O::choice("layout", "L", {"fsl", "mrtrix", "symmatrix", "dtitk"}, "fsl",
                  "on-disk layout of OUT (fsl: xx xy xz yy yz zz in the bvec frame)"),
        O::choice("method", "M", {"wls", "ols"}, "wls", "the fit"),
        O::number("b0-threshold", "B", defaults.b0Threshold, atLeast(0), "b-values <= B s/mm^2 count as b=0"),
        O::integer("threads", "N", defaults.threads, atLeast(0), "worker threads, 0 = all cores"),
        O::flag("force", "overwrite an existing OUT (never an input)"),
        O::integer("bootstrap", "N", 0, closedRange(0, 100000),
                   "wild bootstrap with N resamples (Rademacher-signed residuals, refit with the fit's weights): "
                   "writes --cone and --fa-sd; 0 = none")
            .under("Uncertainty"),
        O::text("cone", "FILE",
                "with --bootstrap: the 95 % cone of uncertainty of the principal direction, degrees (NIfTI on "
                "the DWI grid, NaN outside the mask); `render --uncertainty FILE` shows it"),
        O::text("fa-sd", "FILE", "with --bootstrap: the standard deviation of FA over the resamples (NIfTI)"),
    };
    return t;
  }();
  return table;
}

int cmdFit(const CommandArgs& argv) {
  ParsedOptions args(fitOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const std::string dwiPath = args.positional(0, "DWI volume (see --help)");
  const auto output = std::optional<std::string>(args.required("output"));
  if (!io::isWritableTensorName(*output))
    throw UsageError("the output must be a .nii, .nii.gz, .mif, .mif.gz, .mih or .nrrd file, got '" +
                     *output + "'");
  auto bval = args.get("bval");
  auto bvec = args.get("bvec");
  const auto maskPath = args.get("mask");
  const io::TensorLayout layout = io::parseLayout(args.text("layout"));
  io::FitOptions options;
  options.method = args.text("method") == "ols" ? io::FitMethod::Ols : io::FitMethod::Wls;
  options.b0Threshold = args.number("b0-threshold");
  options.threads = args.integer("threads");
  const bool force = args.flag("force");
  io::BootstrapOptions bootstrap;
  bootstrap.resamples = args.integer("bootstrap");
  const auto conePath = args.get("cone");
  const auto faSdPath = args.get("fa-sd");
  args.finish();
  if (bootstrap.resamples == 1) throw UsageError("--bootstrap needs at least 2 resamples");
  if ((conePath || faSdPath) && bootstrap.resamples == 0)
    throw UsageError("--cone and --fa-sd need --bootstrap N (e.g. --bootstrap 200)");
  if (bootstrap.resamples > 0 && !conePath && !faSdPath)
    throw UsageError("--bootstrap needs --cone FILE and/or --fa-sd FILE to write its result to");
  std::vector<std::string> outputs{*output};
  for (const auto& p : {conePath, faSdPath})
    if (p) {
      if (!io::isWritableVolumeName(*p))
        throw UsageError("the bootstrap maps are NIfTI (.nii or .nii.gz), got '" + *p + "'");
      outputs.push_back(*p);
    }
  io::refuseSameOutputs(outputs);

  const bool embedded = !bval && !bvec && io::hasEmbeddedGradients(dwiPath);
  if (embedded) bval = bvec = std::string();
  if (!bval) bval = sibling(dwiPath, ".bval");
  if (!bvec) bvec = sibling(dwiPath, ".bvec");
  if (!bval) throw InputError("no --bval given and no .bval file beside " + dwiPath);
  if (!bvec) throw InputError("no --bvec given and no .bvec file beside " + dwiPath);

  std::vector<std::string> inputs{dwiPath};
  if (!embedded) inputs.insert(inputs.end(), {*bval, *bvec});
  if (maskPath) inputs.push_back(*maskPath);
  for (const auto& out : outputs) {
    io::refuseUnwritableOutput(out); // before the fit, which can take minutes
    io::refuseOverwritingInput(out, inputs);
    if (!force && io::outputExists(out)) throw InputError(out + " exists (use --force to overwrite it)");
  }

  const auto start = std::chrono::steady_clock::now();
  io::Dwi dwi = io::readDwi(dwiPath, *bval, *bvec, options.b0Threshold);
  MaskVolume mask;
  if (maskPath) {
    try {
      ScalarVolume m = io::readScalarVolume(*maskPath);
      if (m.components != 1)
        throw InputError("a mask must be 3D; it has " + std::to_string(m.components) + " volumes");
      mask = MaskVolume(m.grid, 1, 0);
      for (std::size_t i = 0; i < m.data.size(); ++i)
        mask.data[i] = m.data[i] != 0 ? 1 : 0;
    } catch (...) {
      rethrowWithContext("while reading mask " + *maskPath);
    }
  }
  const auto& d = dwi.signal.grid.dims;
  std::fprintf(stderr, "%s: %dx%dx%d, %d volumes; %s fit, %s\n", dwiPath.c_str(), d.x, d.y, d.z,
               dwi.signal.components, options.method == io::FitMethod::Wls ? "WLS" : "OLS",
               maskPath ? ("mask " + *maskPath).c_str() : "automatic mask");
  io::FitStats stats;
  ProgressPrinter printer;
  if (bootstrap.resamples > 0) {
    printer.label = "bootstrap";
    std::fprintf(stderr, "wild bootstrap: %d resamples\n", bootstrap.resamples);
  }
  TensorField field;
  io::UncertaintyMaps maps;
  try {
    const MaskVolume* m = maskPath ? &mask : nullptr;
    field = bootstrap.resamples > 0 ? io::bootstrapTensors(dwi, m, options, bootstrap, maps, std::ref(printer), &stats)
                                    : io::fitTensors(dwi, m, options, std::ref(printer), &stats);
  } catch (...) {
    if (printer.tty) std::fputc('\n', stderr);
    rethrowWithContext("while fitting " + dwiPath + (maskPath ? " with mask " + *maskPath : ""));
  }
  io::OutputBatch batch; // the tensors and the bootstrap maps together, or none of them
  io::writeTensorVolume(*output, field, layout);
  if (conePath)
    io::writeScalarVolume(*conePath, maps.cone, 1,
                          "dtfabric cone95 deg, wild bootstrap N=" + std::to_string(bootstrap.resamples));
  if (faSdPath)
    io::writeScalarVolume(*faSdPath, maps.faSd, 1,
                          "dtfabric FA sd, wild bootstrap N=" + std::to_string(bootstrap.resamples));
  batch.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "fitted %zu voxels (%zu not positive definite, %zu invalid, %zu signals clamped)\n",
               stats.voxelsFitted, stats.nonPositiveTensors, stats.invalidVoxels, stats.clampedSignals);
  const std::string written =
      io::detectFormat(*output).format == io::FileFormat::Nifti
          ? std::string(io::layoutName(layout)) + " layout"
          : std::string(io::formatName(io::detectFormat(*output).format)) + ", its own convention";
  std::printf("wrote %s (%s) in %.2f s\n", output->c_str(), written.c_str(), seconds);
  if (conePath) std::printf("wrote %s (95 %% cone of uncertainty, degrees)\n", conePath->c_str());
  if (faSdPath) std::printf("wrote %s (bootstrap standard deviation of FA)\n", faSdPath->c_str());
  return 0;
}

} // namespace dtf::app
