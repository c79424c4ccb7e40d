// SPDX-License-Identifier: GPL-3.0-or-later
// `dtfabric bench io`, per-format part: load times of the real tensor (iu_prisma_dwi, 72x72x39) through
// every tensor format dtfabric reads, from files written once into a temporary folder (the MRtrix .mif.gz
// is MRtrix's own file). Medians of a few loads, wall and process CPU.
#include "app/bench/bench.h"
#include "io/model/error.h"
#include "io/model/tensor.h"
#include "io/formats/tensor_io.h"

#include <chrono>
#include <ctime>
#include <unistd.h>

namespace dtf::app {

namespace fs = std::filesystem;

namespace {

void writeDtifitSet(const fs::path& dir, const TensorField& field) {
  glm::dmat3 rf = field.grid.rotation();
  if (glm::determinant(glm::dmat3(field.grid.voxelToWorld)) > 0) rf[0] = -rf[0];
  std::vector<ScalarVolume> v(3, ScalarVolume(field.grid, 3)), l(3, ScalarVolume(field.grid, 1));
  for (std::size_t i = 0; i < field.tensors.size(); ++i) {
    if (!field.valid[i]) continue;
    const EigenSystem e = eigenDecompose(field.tensors[i]);
    for (std::size_t n = 0; n < 3; ++n) {
      const glm::dvec3 f = glm::transpose(rf) * e.vectors[static_cast<int>(n)];
      for (int c = 0; c < 3; ++c)
        v[n].data[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(f[c]);
      l[n].data[i] = static_cast<float>(e.values[static_cast<int>(n)]);
    }
  }
  for (std::size_t n = 0; n < 3; ++n) {
    io::writeScalarVolume((dir / ("dti_V" + std::to_string(n + 1) + ".nii.gz")).string(), v[n]);
    io::writeScalarVolume((dir / ("dti_L" + std::to_string(n + 1) + ".nii.gz")).string(), l[n]);
  }
}

} // namespace

std::vector<FormatLoadFigure> benchFormatLoads(const std::optional<fs::path>& dataDir,
                                               std::vector<std::string>& notes) {
  std::vector<FormatLoadFigure> out;
  const fs::path derived = dataDir ? *dataDir / "iu_prisma_dwi" / "derived" : fs::path();
  if (!dataDir || !fs::exists(derived / "dti_tensor.nii.gz") || !fs::exists(derived / "dti_tensor.mif.gz")) {
    notes.emplace_back("per-format loads skipped: no iu_prisma_dwi/derived tensors found");
    return out;
  }
  const fs::path dir = fs::temp_directory_path() / ("dtfabric-bench-formats-" + std::to_string(getpid()));
  fs::create_directories(dir);
  try {
    const TensorField field = io::readTensorVolume((derived / "dti_tensor.nii.gz").string()).field;
    io::writeTensorVolume((dir / "t.mif").string(), field, io::TensorLayout::Mrtrix);
    io::writeTensorVolume((dir / "t.nrrd").string(), field, io::TensorLayout::Fsl);
    writeDtifitSet(dir, field);
    const std::pair<std::string, std::string> files[] = {
        {"nifti_gz", (derived / "dti_tensor.nii.gz").string()},
        {"mif_gz", (derived / "dti_tensor.mif.gz").string()},
        {"mif", (dir / "t.mif").string()},
        {"nrrd_gz", (dir / "t.nrrd").string()},
        {"dtifit_set", (dir / "dti").string()}};
    for (const auto& [key, path] : files) {
      FormatLoadFigure f;
      f.key = "load_" + key + "_s";
      f.label = "load 72x72x39 tensor, " + key;
      std::vector<double> wall, cpu;
      for (int r = 0; r < 5; ++r) {
        const auto start = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        io::readTensorVolume(path);
        cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      f.wall = median(wall);
      f.cpu = median(cpu);
      out.push_back(f);
    }
  } catch (const Error& e) {
    notes.push_back(std::string("per-format loads stopped: ") + e.what());
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return out;
}

} // namespace dtf::app
