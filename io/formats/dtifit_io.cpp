// SPDX-License-Identifier: GPL-3.0-or-later
// FSL dtifit outputs without --save_tensor: <base>_V1.._V3 (eigenvectors, 3 volumes each), <base>_L1.._L3
// (eigenvalues, mm^2/s), plus _FA, _MD, _MO, _S0. The tensor is D = sum_i L_i V_i V_i^T in FSL's frame (the
// voxel axes, with x negated when det(affine) > 0, as bvec files), then rotated to world RAS like the FSL
// tensor layout: D_world = R D R^T.
#include "io/formats/format_detail.h"
#include "io/model/error.h"

#include <array>
#include <filesystem>

namespace fs = std::filesystem;

namespace dtf::io::detail {

namespace {

constexpr std::array<const char*, 10> kMembers = {"V1", "V2", "V3", "L1", "L2", "L3", "FA", "MD", "MO", "S0"};

// <base>_<member>, or <dir>/<member> for a set without a prefix (base ending in '/': FA.nii.gz, V1.nii.gz).
std::string memberName(const std::string& base, const std::string& member) {
  return base.empty() || base.back() == '/' ? base + member : base + "_" + member;
}

std::string memberFile(const std::string& base, const std::string& member) {
  return dtifitMemberFile(base, member);
}

// Any of V1-V3, L1-L3 (the reader then names what is missing).
bool hasEigenFiles(const std::string& base) {
  for (std::size_t m = 0; m < 6; ++m)
    if (!memberFile(base, kMembers[m]).empty()) return true;
  return false;
}

} // namespace

std::string dtifitMemberFile(const std::string& base, const std::string& member) {
  std::error_code ec;
  for (const char* ext : {".nii.gz", ".nii"}) {
    const std::string p = memberName(base, member) + ext;
    if (fs::is_regular_file(p, ec)) return p;
  }
  return {};
}

std::string dtifitBasename(const std::string& path) {
  std::string stem = path;
  for (const char* ext : {".nii.gz", ".nii"})
    if (endsWith(stem, ext)) {
      stem.resize(stem.size() - std::string(ext).size());
      break;
    }
  const std::string file = fs::path(stem).filename().string();
  for (const char* m : kMembers) {
    const std::string suffix = std::string("_") + m;
    if (endsWith(stem, suffix) && file.size() > suffix.size()) {
      const std::string base = stem.substr(0, stem.size() - suffix.size());
      return hasEigenFiles(base) ? base : std::string();
    }
    if (file == m) { // unprefixed set: <dir>/V1.nii.gz
      std::string base = stem.substr(0, stem.size() - file.size());
      if (base.empty()) base = "./";
      return hasEigenFiles(base) ? base : std::string();
    }
  }
  std::error_code ec;
  if (!fs::exists(path, ec) && hasEigenFiles(stem)) return stem;
  return {};
}

VolumeHeader dtifitHeader(const std::string& path) {
  const std::string base = dtifitBasename(path);
  if (base.empty()) throw InputError(path + ": not an FSL dtifit set (no _V1-_V3 or _L1-_L3 file beside it)");
  std::string first;
  for (const char* m : {"L1", "V1", "L2", "L3", "V2", "V3"})
    if (first.empty()) first = memberFile(base, m);
  VolumeHeader h = readNiftiHeader(first);
  // Described as what it reads as: six tensor components per voxel.
  h.dims.resize(3, 1);
  h.dims.push_back(6);
  h.intentName = "FSL dtifit eigen-system (tensor from L1-L3, V1-V3)";
  h.path = base;
  return h;
}

LoadedTensors readDtifit(const std::string& path) {
  const std::string base = dtifitBasename(path);
  if (base.empty()) throw InputError(path + ": not an FSL dtifit set (no _V1-_V3 or _L1-_L3 file beside it)");
  std::string found, missing;
  std::vector<std::string> files(6);
  for (int m = 0; m < 6; ++m) {
    files[static_cast<std::size_t>(m)] = memberFile(base, kMembers[static_cast<std::size_t>(m)]);
    std::string& list = files[static_cast<std::size_t>(m)].empty() ? missing : found;
    list += (list.empty() ? "" : ", ") + std::string(kMembers[static_cast<std::size_t>(m)]);
  }
  std::string extras;
  for (std::size_t m = 6; m < kMembers.size(); ++m)
    if (!memberFile(base, kMembers[m]).empty())
      extras += (extras.empty() ? "" : ", ") + std::string(kMembers[m]);
  if (!missing.empty()) {
    std::string msg = path + ": FSL dtifit set " + base + ": found " + found +
                      (extras.empty() ? "" : ", " + extras) + "; missing " + missing +
                      ": a tensor needs V1-V3 and L1-L3 (no " + memberName(base, missing.substr(0, 2)) +
                      ".nii[.gz])";
    if (!files[0].empty() && files[3].empty() && files[4].empty() && files[5].empty())
      msg += "; with V1 alone it is a one-population fibre set, which `dtfabric render` and `info` read";
    else if (found.empty())
      msg = path + ": FSL dtifit set " + base + ": no V1-V3 or L1-L3 files";
    throw InputError(msg);
  }
  LoadedTensors out;
  VolumeHeader ref;
  std::vector<ScalarVolume> vols(6);
  for (int m = 0; m < 6; ++m) {
    VolumeHeader h;
    vols[static_cast<std::size_t>(m)] = readNiftiScalarVolume(files[static_cast<std::size_t>(m)], &h);
    const int want = m < 3 ? 3 : 1;
    if (vols[static_cast<std::size_t>(m)].components != want)
      throw InputError(files[static_cast<std::size_t>(m)] + ": a dtifit " +
                       kMembers[static_cast<std::size_t>(m)] + " file holds " + std::to_string(want) +
                       " volume(s), this one " +
                       std::to_string(vols[static_cast<std::size_t>(m)].components));
    if (m == 0) {
      ref = h;
      continue;
    }
    if (h.grid.dims != ref.grid.dims)
      throw InputError(files[static_cast<std::size_t>(m)] + ": grid differs from " + files[0]);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r)
        if (std::abs(h.grid.voxelToWorld[c][r] - ref.grid.voxelToWorld[c][r]) > 1e-3)
          throw InputError(files[static_cast<std::size_t>(m)] + ": affine differs from " + files[0]);
  }
  out.header = ref;
  out.header.dims.resize(3, 1);
  out.header.dims.push_back(6);
  out.header.path = base;
  out.header.intentName = "FSL dtifit eigen-system (tensor from L1-L3, V1-V3)";
  out.warnings = ref.warnings;
  out.layout = TensorLayout::Fsl;
  out.layoutReason = "FSL dtifit eigen-system " + base + ": found " + found +
                     (extras.empty() ? "" : ", " + extras) +
                     "; D = sum L_i V_i V_i^T in FSL's frame (voxel axes, x negated when det(affine) > 0), "
                     "then rotated to world";
  const Grid& g = ref.grid;
  glm::dmat3 r = g.rotation();
  if (glm::determinant(glm::dmat3(g.voxelToWorld)) > 0) r[0] = -r[0];
  out.field = makeTensorField(g);
  const std::size_t nv = g.voxelCount();
  for (std::size_t i = 0; i < nv; ++i) {
    glm::dmat3 d(0.0);
    for (int e = 0; e < 3; ++e) {
      const float* v = &vols[static_cast<std::size_t>(e)].data[i * 3];
      const double l = vols[static_cast<std::size_t>(e) + 3].data[i];
      const glm::dvec3 vec(v[0], v[1], v[2]);
      d += l * glm::outerProduct(vec, vec);
    }
    storeWorldTensor(out, i, r * d * glm::transpose(r));
  }
  if (out.nanVoxels)
    out.warnings.push_back(std::to_string(out.nanVoxels) + " voxel(s) hold NaN/Inf values (marked invalid)");
  return out;
}

} // namespace dtf::io::detail
