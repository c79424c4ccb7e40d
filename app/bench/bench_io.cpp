// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench io`: load time of an HCP-sized tensor volume, FA-map time, and tensor-fit times of the
// real DWI and of a 1.5 mm upsampled copy, each the median of a few runs, beside their goals.
#include "app/bench/bench.h"
#include "app/command/options.h"
#include "app/command/args.h"
#include "io/diffusion/dwi.h"
#include "io/model/error.h"
#include "io/formats/tensor_io.h"
#include "io/diffusion/uncertainty.h"
#include "io/formats/json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace dtf::app {

namespace {

namespace fs = std::filesystem;

struct Timing {
  double wall = -1; // median wall-clock seconds; < 0: not measured
  double cpu = -1;  // median process CPU seconds (all threads), which load from other processes inflates less
};

// Median wall and CPU time of `runs` calls.
Timing medianTiming(int runs, const std::function<void()>& f) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    f();
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

// HCP-sized (145x174x145, 1.25 mm, LAS like the HCP release) synthetic brain: an ellipsoid of tensors whose
// principal direction circles the z axis, FA about 0.6, MD 0.8e-3 mm^2/s; invalid outside.
TensorField hcpSizedField() {
  glm::dmat4 a(1.0);
  a[0][0] = -1.25;
  a[1][1] = 1.25;
  a[2][2] = 1.25;
  a[3] = glm::dvec4(90, -126, -72, 1);
  TensorField f = makeTensorField(Grid::fromAffine({145, 174, 145}, a));
  const glm::dvec3 c(72, 87, 72), r(62, 78, 60);
  for (int k = 0; k < 145; ++k)
    for (int j = 0; j < 174; ++j)
      for (int i = 0; i < 145; ++i) {
        glm::dvec3 p = (glm::dvec3(i, j, k) - c) / r;
        if (glm::dot(p, p) > 1) continue;
        glm::dvec3 e1 = glm::dvec3(-p.y, p.x, 0.3 * p.z + 0.05);
        e1 = glm::normalize(e1);
        glm::dmat3 d = 0.4e-3 * glm::dmat3(1.0) + 1.2e-3 * glm::outerProduct(e1, e1);
        const std::size_t idx = f.grid.index(i, j, k);
        f.tensors[idx] = SymTensor::fromMat(d);
        f.valid[idx] = 1;
      }
  return f;
}

// Trilinear x2 upsampling of every volume (voxel centres of the new grid at old index n/2 - 0.25, so the
// field of view is unchanged); the mask is upsampled by nearest neighbour.
void upsample2(const io::Dwi& in, const MaskVolume& mask, io::Dwi& out, MaskVolume& outMask) {
  const Grid& g = in.signal.grid;
  glm::dmat4 t(1.0);
  t[0][0] = t[1][1] = t[2][2] = 0.5;
  t[3] = glm::dvec4(-0.25, -0.25, -0.25, 1);
  Grid ng = Grid::fromAffine(g.dims * 2, g.voxelToWorld * t);
  const int n = in.signal.components;
  out.signal = Volume<float>(ng, n);
  out.bvals = in.bvals;
  out.gradientsWorld = in.gradientsWorld;
  outMask = MaskVolume(ng, 1, 0);
  auto split = [](int ni, int dim, int& i0, int& i1, double& w) {
    double x = std::clamp(ni * 0.5 - 0.25, 0.0, static_cast<double>(dim - 1));
    i0 = static_cast<int>(std::floor(x));
    i1 = std::min(i0 + 1, dim - 1);
    w = x - i0;
  };
  for (int k = 0; k < ng.dims.z; ++k) {
    int k0, k1;
    double wk;
    split(k, g.dims.z, k0, k1, wk);
    for (int j = 0; j < ng.dims.y; ++j) {
      int j0, j1;
      double wj;
      split(j, g.dims.y, j0, j1, wj);
      for (int i = 0; i < ng.dims.x; ++i) {
        int i0, i1;
        double wi;
        split(i, g.dims.x, i0, i1, wi);
        const std::size_t c[8] = {g.index(i0, j0, k0), g.index(i1, j0, k0), g.index(i0, j1, k0),
                                  g.index(i1, j1, k0), g.index(i0, j0, k1), g.index(i1, j0, k1),
                                  g.index(i0, j1, k1), g.index(i1, j1, k1)};
        const double w[8] = {(1 - wi) * (1 - wj) * (1 - wk),
                             wi * (1 - wj) * (1 - wk),
                             (1 - wi) * wj * (1 - wk),
                             wi * wj * (1 - wk),
                             (1 - wi) * (1 - wj) * wk,
                             wi * (1 - wj) * wk,
                             (1 - wi) * wj * wk,
                             wi * wj * wk};
        float* dst = &out.signal.data[ng.index(i, j, k) * n];
        for (int v = 0; v < n; ++v) {
          double s = 0;
          for (int q = 0; q < 8; ++q)
            s += w[q] * in.signal.data[c[q] * n + v];
          dst[v] = static_cast<float>(s);
        }
        outMask.at(i, j, k) = mask.at(std::min(i / 2, g.dims.x - 1), std::min(j / 2, g.dims.y - 1),
                                      std::min(k / 2, g.dims.z - 1));
      }
    }
  }
}

MaskVolume toMask(const ScalarVolume& v) {
  MaskVolume m(v.grid, 1, 0);
  for (std::size_t i = 0; i < m.data.size(); ++i)
    m.data[i] = v.data[i] != 0 ? 1 : 0;
  return m;
}

struct Figure {
  const char* key;
  const char* label;
  Timing t;
  double goal;
  const char* goalText;
};

// Tensor load and FA map on the HCP-sized field.
void timeHcpSized(Figure& load, Figure& fa, std::vector<std::string>& notes) {
  TensorField field = hcpSizedField();
  fs::path dir = fs::temp_directory_path() / ("dtfabric-bench-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string file = (dir / "hcp_sized_tensor.nii.gz").string();
  try {
    io::writeTensorVolume(file, field, io::TensorLayout::Fsl);
    load.t = medianTiming(3, [&] { io::readTensorVolume(file, io::TensorLayout::Auto); });
  } catch (const Error& e) {
    notes.push_back(std::string("tensor load skipped: ") + e.what());
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  computeFaMap(field); // warm-up
  fa.t = medianTiming(5, [&] { computeFaMap(field); });
}

// WLS fits of the real DWI in its mask and of a 2x upsampled copy.
void timeFits(const std::optional<fs::path>& dataDir, int threads, Figure& fitReal, Figure& fitUp,
              std::vector<std::string>& notes) {
  const fs::path dwiDir = dataDir ? *dataDir / "iu_prisma_dwi" : fs::path();
  if (!dataDir || !fs::exists(dwiDir / "dwi.nii.gz") || !fs::exists(dwiDir / "derived" / "mask.nii.gz")) {
    notes.push_back("fit skipped: no iu_prisma_dwi data found (use --data DIR or DTF_SHARED_DATA)");
    return;
  }
  io::Dwi dwi = io::readDwi((dwiDir / "dwi.nii.gz").string(), (dwiDir / "dwi.bval").string(),
                            (dwiDir / "dwi.bvec").string());
  MaskVolume mask = toMask(io::readScalarVolume((dwiDir / "derived" / "mask.nii.gz").string()));
  io::FitOptions o;
  o.threads = threads;
  io::fitTensors(dwi, &mask, o); // warm-up
  fitReal.t = medianTiming(7, [&] { io::fitTensors(dwi, &mask, o); });
  io::Dwi up;
  MaskVolume upMask;
  upsample2(dwi, mask, up, upMask);
  fitUp.t = medianTiming(5, [&] { io::fitTensors(up, &upMask, o); });
}

// A 200-resample wild bootstrap (WLS, automatic mask) of the bundled brain, once (it takes seconds).
void timeBootstrap(const std::string& dwiPath, int threads, Figure& boot, std::vector<std::string>& notes) {
  if (!fs::exists(dwiPath)) {
    notes.push_back("bootstrap skipped: no " + dwiPath + " (run from the source tree or give --sample-dwi)");
    return;
  }
  try {
    std::string base = dwiPath;
    for (const std::string ext : {".nii.gz", ".nii"})
      if (base.size() > ext.size() && base.compare(base.size() - ext.size(), ext.size(), ext) == 0) {
        base.resize(base.size() - ext.size());
        break;
      }
    const io::Dwi dwi = io::readDwi(dwiPath, base + ".bval", base + ".bvec");
    io::FitOptions o;
    o.threads = threads;
    io::BootstrapOptions b;
    b.resamples = 200;
    io::UncertaintyMaps maps;
    io::FitStats stats;
    boot.t = medianTiming(1, [&] { io::bootstrapTensors(dwi, nullptr, o, b, maps, {}, &stats); });
    notes.push_back("bootstrap: " + std::to_string(stats.voxelsFitted) + " voxels x 200 resamples of " +
                    dwiPath);
  } catch (const Error& e) {
    notes.push_back(std::string("bootstrap skipped: ") + e.what());
  }
}

} // namespace

const OptionTable& benchIoOptions() {
  using O = CliOption;
  static const OptionTable table = [] {
    OptionTable t;
    t.command = "bench io";
    t.intro =
        "Times loading an HCP-sized (145x174x145) tensor .nii.gz, its FA map, and WLS tensor fits\n"
        "of the real DWI (DIR/iu_prisma_dwi, with its mask) and of a 1.5 mm upsampled copy;\n"
        "load times of the real tensor as NIfTI, MRtrix .mif/.mif.gz, NRRD and a dtifit set;\n"
        "tractogram loads: DIR/niivue_tracts/stroke.trk.gz beside nibabel's load of it (when\n"
        "python3-nibabel is present) and a TRX of 1 M streamlines made here; a 200-resample wild\n"
        "bootstrap of the bundled brain (--sample-dwi). The fit figures are skipped when the shared data\n"
        "are not found. Medians of a few runs.";
    t.options = {
        O::flag("json", "one JSON object"),
        sharedDataOption(),
        O::integer("threads", "N", 0, atLeast(0), "fit threads, 0 = all cores"),
        O::text("sample-dwi", "FILE", "the DWI of the bootstrap figure (its .bval/.bvec beside it)",
                "sample_data/dwi.nii.gz"),
    };
    return t;
  }();
  return table;
}

int benchIo(const CommandArgs& argv) {
  ParsedOptions args(benchIoOptions(), argv);
  if (args.printHelpIfAsked()) return 0;
  const bool json = args.flag("json");
  const auto dataArg = args.get("data");
  const int threads = args.integer("threads");
  const std::string sampleDwi = args.text("sample-dwi");
  args.finish();

  std::vector<std::string> notes;
  Figure load{"tensor_load_s", "load 145x174x145 tensor .nii.gz", {}, 1.0, "< 1 s"};
  Figure fa{"fa_map_s", "FA map 145x174x145", {}, 0.1, "< 100 ms"};
  Figure fitReal{"fit_real_s", "fit 72x72x39x21 (mask)", {}, 0.13, "<= 0.13 s (MRtrix dwi2tensor)"};
  Figure fitUp{"fit_upsampled_s", "fit 144x144x78x21 (mask)", {}, 1.2, "<= 1.2 s (MRtrix dwi2tensor)"};
  Figure boot{"bootstrap_200_s", "wild bootstrap x200, bundled brain", {}, 10.0, "<= 10 s"};

  timeHcpSized(load, fa, notes);
  const auto dataDir = findSharedDataDir(dataArg);
  timeFits(dataDir, threads, fitReal, fitUp, notes);
  timeBootstrap(sampleDwi, threads, boot, notes);

  const std::vector<TractLoadFigure> tractLoads = benchTractLoads(dataDir, notes);
  std::vector<Figure> tractFigures;
  for (const auto& t : tractLoads)
    tractFigures.push_back({t.key.c_str(), t.label.c_str(), {t.wall, t.cpu}, t.goal, t.goalText.c_str()});
  const std::vector<FormatLoadFigure> formats = benchFormatLoads(dataDir, notes);

  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const double load1 = loadAverage();
  std::vector<const Figure*> figures = {&load, &fa, &fitReal, &fitUp, &boot};
  for (const auto& f : tractFigures)
    figures.push_back(&f);
  if (json) {
    nlohmann::ordered_json j = {{"threads", threads}, {"cores", cores}, {"load_average", load1}};
    for (const Figure* f : figures) {
      const std::string key = f->key;
      j[key] = f->t.wall >= 0 ? nlohmann::ordered_json(f->t.wall) : nlohmann::ordered_json();
      j[key + "_cpu"] = f->t.wall >= 0 ? nlohmann::ordered_json(f->t.cpu) : nlohmann::ordered_json();
      j[key + "_goal"] = f->goal;
    }
    for (const FormatLoadFigure& f : formats) {
      j[f.key] = f.wall;
      j[f.key + "_cpu"] = f.cpu;
    }
    j["notes"] = notes;
    std::printf("%s\n", io::jsonText(j).c_str());
  } else {
    std::printf("bench io (%u cores, threads %s, load average %.2f; medians, wall and process CPU)\n", cores,
                threads > 0 ? std::to_string(threads).c_str() : "all", load1);
    for (const Figure* f : figures) {
      if (f->t.wall >= 0)
        std::printf("  %-32s %8.1f ms wall %8.1f ms cpu   goal %-30s %s\n", f->label, f->t.wall * 1e3,
                    f->t.cpu * 1e3, f->goalText, f->t.wall <= f->goal ? "ok" : "SLOWER");
      else
        std::printf("  %-32s %12s   goal %s\n", f->label, "skipped", f->goalText);
    }
    for (const FormatLoadFigure& f : formats)
      std::printf("  %-32s %8.1f ms wall %8.1f ms cpu\n", f.label.c_str(), f.wall * 1e3, f.cpu * 1e3);
    if (load1 > cores)
      std::printf("  note: the load average exceeds the core count; wall times are inflated by other work\n");
    for (const auto& n : notes)
      std::printf("  note: %s\n", n.c_str());
  }
  return 0;
}

} // namespace dtf::app
