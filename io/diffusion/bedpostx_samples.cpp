// SPDX-License-Identifier: GPL-3.0-or-later
// FSL bedpostx direction samples as cones of uncertainty, and cone maps for display (io/uncertainty.h).
#include "io/diffusion/fit_detail.h"
#include "io/diffusion/uncertainty.h"
#include "io/formats/fibre_io.h"
#include "io/formats/tensor_io.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>

namespace dtf::io {

namespace {

namespace fs = std::filesystem;

std::string existing(const fs::path& folder, const std::string& stem) {
  for (const char* ext : {".nii.gz", ".nii"}) {
    const fs::path p = folder / (stem + ext);
    if (fs::exists(p)) return p.string();
  }
  return {};
}

const std::regex& samplesName() {
  static const std::regex r(R"(merged_(th|ph|f)\d+samples\.nii(\.gz)?)");
  return r;
}

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw InputError(file + ": " + what);
}

} // namespace

bool isBedpostxSamplesPath(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return !existing(path, "merged_th1samples").empty();
  return std::regex_match(fs::path(path).filename().string(), samplesName());
}

BedpostxSamples readBedpostxSamples(const std::string& path, double percentile, double minFraction) {
  std::error_code ec;
  fs::path folder = fs::is_directory(path, ec) ? fs::path(path) : fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  BedpostxSamples out;
  for (int pop = 1; pop <= 16; ++pop) {
    const std::string id = std::to_string(pop);
    const std::string th = existing(folder, "merged_th" + id + "samples");
    if (th.empty()) {
      if (pop == 1)
        fail(path,
             "no merged_th1samples.nii.gz in " + folder.string() + " (not a bedpostx folder with samples)");
      break;
    }
    const std::string ph = existing(folder, "merged_ph" + id + "samples");
    const std::string fr = existing(folder, "merged_f" + id + "samples");
    if (ph.empty()) fail(th, "has no partner " + (folder / ("merged_ph" + id + "samples.nii.gz")).string());
    if (fr.empty()) fail(th, "has no partner " + (folder / ("merged_f" + id + "samples.nii.gz")).string());
    const ScalarVolume vt = readScalarVolume(th), vp = readScalarVolume(ph), vf = readScalarVolume(fr);
    out.files.insert(out.files.end(), {th, ph, fr});
    if (pop == 1) {
      out.grid = vt.grid;
      out.samples = vt.components;
    }
    for (const auto* f : {&vt, &vp, &vf}) {
      const std::string& name = f == &vt ? th : (f == &vp ? ph : fr);
      if (!f->grid.sameAs(out.grid)) fail(name, "its grid differs from " + out.files[0]);
      if (f->components != out.samples)
        fail(name, "has " + std::to_string(f->components) + " samples; " + out.files[0] + " has " +
                       std::to_string(out.samples));
    }
    const int n = out.samples;
    const glm::dmat3 m = fibreFrameToWorld(out.grid, FibreLayout::Bedpostx);
    const std::size_t count = out.grid.voxelCount();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    ScalarVolume cone(out.grid, 1, nan), meanF(out.grid, 1, 0.0f);
    Volume<float> mean(out.grid, 3, 0.0f);
    std::vector<glm::vec3> dirs(static_cast<std::size_t>(n));
    for (std::size_t v = 0; v < count; ++v) {
      double fsum = 0;
      for (int s = 0; s < n; ++s)
        fsum += vf.data[v * n + s];
      const double fm = fsum / n;
      if (!std::isfinite(fm)) fail(fr, "voxel " + std::to_string(v) + " holds NaN/Inf");
      meanF.data[v] = static_cast<float>(fm);
      if (!(fm >= minFraction)) continue;
      for (int s = 0; s < n; ++s) {
        const double t = vt.data[v * n + s], p = vp.data[v * n + s];
        if (!std::isfinite(t) || !std::isfinite(p))
          fail(th, "voxel " + std::to_string(v) + " holds NaN/Inf angles");
        dirs[static_cast<std::size_t>(s)] =
            glm::vec3(m * glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)));
      }
      const DirectionSpread spread = directionSpread(dirs.data(), dirs.size(), percentile);
      cone.data[v] = static_cast<float>(spread.coneDeg);
      for (int c = 0; c < 3; ++c)
        mean.data[v * 3 + c] = static_cast<float>(spread.mean[c]);
    }
    out.cone.push_back(std::move(cone));
    out.mean.push_back(std::move(mean));
    out.meanFraction.push_back(std::move(meanF));
  }
  return out;
}

ScalarVolume readConeMap(const std::string& path) {
  if (isBedpostxSamplesPath(path)) return std::move(readBedpostxSamples(path).cone.at(0));
  ScalarVolume v = readScalarVolume(path);
  if (v.components != 1)
    fail(path, "has " + std::to_string(v.components) +
                   " volumes; a cone map is 3D (degrees), e.g. from dtfabric fit --bootstrap N --cone FILE");
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    const float c = v.data[i];
    if (std::isnan(c)) continue;
    if (!(c >= 0.0f && c <= 90.001f))
      fail(path, "holds " + std::to_string(c) + " at voxel index " + std::to_string(i) +
                     "; a cone of uncertainty lies in [0, 90] degrees (NaN: none)");
  }
  return v;
}

} // namespace dtf::io
