// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/tensor_field.h"

#include "io/model/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace dtf {

TensorField makeTensorField(const Grid& grid) {
  TensorField f;
  f.grid = grid;
  assignAdvised(f.tensors, grid.voxelCount(), SymTensor{});
  assignAdvised(f.valid, grid.voxelCount(), static_cast<unsigned char>(0));
  return f;
}

SymTensor TensorField::sample(const glm::dvec3& p) const {
  const glm::ivec3 d = grid.dims;
  if (!(p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x <= d.x - 1 && p.y <= d.y - 1 && p.z <= d.z - 1)) return {};
  int i0 = static_cast<int>(std::floor(p.x)), j0 = static_cast<int>(std::floor(p.y)),
      k0 = static_cast<int>(std::floor(p.z));
  int i1 = std::min(i0 + 1, d.x - 1), j1 = std::min(j0 + 1, d.y - 1), k1 = std::min(k0 + 1, d.z - 1);
  double fx = p.x - i0, fy = p.y - j0, fz = p.z - k0;
  double acc[6] = {0, 0, 0, 0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    int i = (c & 1) ? i1 : i0, j = (c & 2) ? j1 : j0, k = (c & 4) ? k1 : k0;
    double w = ((c & 1) ? fx : 1 - fx) * ((c & 2) ? fy : 1 - fy) * ((c & 4) ? fz : 1 - fz);
    if (w == 0) continue;
    auto comps = at(i, j, k).components();
    for (int n = 0; n < 6; ++n) acc[n] += w * comps[n];
  }
  SymTensor t;
  t.xx = static_cast<float>(acc[0]);
  t.xy = static_cast<float>(acc[1]);
  t.xz = static_cast<float>(acc[2]);
  t.yy = static_cast<float>(acc[3]);
  t.yz = static_cast<float>(acc[4]);
  t.zz = static_cast<float>(acc[5]);
  return t;
}

namespace {
template <typename Fn> void parallelSlices(int nz, Fn fn) {
  unsigned n = std::max(1u, std::min(std::thread::hardware_concurrency(), 16u));
  if (nz < 4) n = 1;
  std::vector<std::thread> workers;
  for (unsigned w = 0; w < n; ++w)
    workers.emplace_back([=, &fn] {
      for (int k = static_cast<int>(w); k < nz; k += static_cast<int>(n)) fn(k);
    });
  for (auto& t : workers) t.join();
}
} // namespace

MetricMaps computeMetricMaps(const TensorField& field, bool withMode, bool withDec) {
  MetricMaps m;
  const Grid& g = field.grid;
  m.fa = ScalarVolume(g, 1);
  m.md = ScalarVolume(g, 1);
  m.ad = ScalarVolume(g, 1);
  m.rd = ScalarVolume(g, 1);
  if (withMode) m.mode = ScalarVolume(g, 1);
  if (withDec) m.dec = Volume<float>(g, 3);
  const std::size_t slice = static_cast<std::size_t>(g.dims.x) * g.dims.y;
  parallelSlices(g.dims.z, [&](int k) {
    for (std::size_t idx = slice * k; idx < slice * (k + 1); ++idx) {
      if (!field.valid[idx]) continue;
      EigenSystem e = eigenDecompose(field.tensors[idx]);
      TensorMetrics tm = computeMetrics(e);
      m.fa.data[idx] = static_cast<float>(tm.fa);
      m.md.data[idx] = static_cast<float>(tm.md);
      m.ad.data[idx] = static_cast<float>(tm.ad);
      m.rd.data[idx] = static_cast<float>(tm.rd);
      if (withMode) m.mode.data[idx] = static_cast<float>(tm.mode);
      if (withDec) {
        glm::dvec3 c = decColor(e, tm.fa);
        for (int ch = 0; ch < 3; ++ch) m.dec.data[idx * 3 + ch] = static_cast<float>(c[ch]);
      }
    }
  });
  return m;
}

ScalarVolume computeFaMap(const TensorField& field) {
  ScalarVolume fa(field.grid, 1);
  const std::size_t slice = static_cast<std::size_t>(field.grid.dims.x) * field.grid.dims.y;
  parallelSlices(field.grid.dims.z, [&](int k) {
    for (std::size_t idx = slice * k; idx < slice * (k + 1); ++idx) {
      if (!field.valid[idx]) continue;
      fa.data[idx] = static_cast<float>(fractionalAnisotropy(field.tensors[idx]));
    }
  });
  return fa;
}

} // namespace dtf
