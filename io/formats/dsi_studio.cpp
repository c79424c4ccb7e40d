// SPDX-License-Identifier: GPL-3.0-or-later
// DSI Studio SRC and FIB files: MATLAB v4 matrices one after another, each with a 20-byte header
// (type = 1000*M + 100*O + 10*P + T, rows, cols, imaginary flag, name length), the name and the values
// column by column. M = 0 little-endian (1 big-endian); P = 0 double, 1 float, 2 int32, 3 int16, 4 uint16,
// 5 uint8; T = 0 numeric (1 text). Images are stored as (nx*ny) x nz, i.e. x fastest.
#include "io/formats/dsi_studio.h"

#include "io/formats/format_detail.h"
#include "io/model/error.h"

#include <cstring>
#include <map>

namespace dtf::io {

namespace {

using detail::fail;
using detail::SampleType;
using detail::SampleTypeInfo;
using detail::sampleTypeInfo;

struct Matrix {
  long long rows = 0, cols = 0;
  std::vector<float> values;
};

// All numeric matrices whose name `want` accepts (text ones are skipped).
std::map<std::string, Matrix> readMatlab4(const std::string& path, bool (*want)(const std::string&)) {
  const std::vector<std::uint8_t> b = detail::readFileBytes(path);
  std::map<std::string, Matrix> out;
  std::size_t p = 0;
  while (p < b.size()) {
    if (b.size() - p < 20) fail(path, "truncated MATLAB v4 matrix header at byte " + std::to_string(p));
    std::int32_t h[5];
    std::memcpy(h, b.data() + p, sizeof h);
    const int type = h[0];
    if (type < 0 || type >= 2000)
      fail(path, "not a MATLAB v4 file (matrix type " + std::to_string(type) + " at byte " +
                     std::to_string(p) + ")");
    const int m = type / 1000, o = (type / 100) % 10, prec = (type / 10) % 10, t = type % 10;
    if (m != 0) fail(path, "big-endian MATLAB v4 matrices are not read");
    if (o != 0 || prec > 5 || t > 1) fail(path, "unsupported MATLAB v4 matrix type " + std::to_string(type));
    if (h[1] < 0 || h[2] < 0 || h[4] < 1 || h[4] > 256)
      fail(path, "bad MATLAB v4 matrix header at byte " + std::to_string(p));
    const long long rows = h[1], cols = h[2];
    if (rows && cols > detail::kMaxValues / rows)
      fail(path, "absurd matrix size " + std::to_string(rows) + "x" + std::to_string(cols));
    // MATLAB v4 precisions 0 double, 1 float, 2 int32, 3 int16, 4 uint16, 5 uint8 onto the sample table.
    static constexpr SampleType kPrecision[6] = {SampleType::Float64, SampleType::Float32, SampleType::Int32,
                                                 SampleType::Int16,   SampleType::UInt16,  SampleType::UInt8};
    const std::size_t count = static_cast<std::size_t>(rows * cols) * (h[3] ? 2 : 1);
    const std::size_t bytes = count * static_cast<std::size_t>(sampleTypeInfo(kPrecision[prec]).bytes);
    p += 20;
    if (b.size() - p < static_cast<std::size_t>(h[4])) fail(path, "truncated matrix name");
    std::string name(reinterpret_cast<const char*>(b.data() + p), static_cast<std::size_t>(h[4]));
    name = name.substr(0, name.find('\0'));
    p += static_cast<std::size_t>(h[4]);
    if (b.size() - p < bytes)
      fail(path, "matrix '" + name + "' is truncated: " + std::to_string(b.size() - p) + " of " +
                     std::to_string(bytes) + " bytes");
    if (t == 0 && !h[3] && want(name)) {
      Matrix mat;
      mat.rows = rows;
      mat.cols = cols;
      mat.values.resize(static_cast<std::size_t>(rows * cols));
      const std::uint8_t* src = b.data() + p;
      const SampleTypeInfo& sample = sampleTypeInfo(kPrecision[prec]);
      for (std::size_t i = 0; i < mat.values.size(); ++i)
        mat.values[i] =
            static_cast<float>(sample.fetch(src + i * static_cast<std::size_t>(sample.bytes), false));
      out[name] = std::move(mat);
    }
    p += bytes;
  }
  return out;
}

const Matrix& need(const std::string& path, const std::map<std::string, Matrix>& m, const std::string& name) {
  const auto it = m.find(name);
  if (it == m.end()) fail(path, "has no '" + name + "' matrix");
  return it->second;
}

// Grid from `dimension` and `voxel_size`: LPS voxel axes, centred on the origin (see
// io/formats/dsi_studio.h).
Grid dsiGrid(const std::string& path, const std::map<std::string, Matrix>& m) {
  const Matrix& d = need(path, m, "dimension");
  const Matrix& v = need(path, m, "voxel_size");
  if (d.values.size() != 3 || v.values.size() != 3)
    fail(path, "'dimension' and 'voxel_size' must hold 3 values");
  glm::ivec3 dims;
  glm::dvec3 vox;
  long long total = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = d.values[static_cast<std::size_t>(a)];
    if (!(n >= 1) || n > 1e6 || n != static_cast<double>(static_cast<long long>(n)))
      fail(path, "bad dimension " + std::to_string(n));
    dims[a] = static_cast<int>(n);
    total *= dims[a];
    vox[a] = v.values[static_cast<std::size_t>(a)];
    if (!(vox[a] > 0) || !std::isfinite(vox[a]))
      fail(path, "voxel size " + std::to_string(vox[a]) + " is not positive");
  }
  if (total > detail::kMaxValues) fail(path, "dimensions are absurd");
  glm::dmat4 a(1.0);
  a[0][0] = -vox.x;
  a[1][1] = -vox.y;
  a[2][2] = vox.z;
  const glm::dvec3 centre = glm::dmat3(a) * (glm::dvec3(dims - 1) * 0.5);
  a[3] = glm::dvec4(-centre, 1.0);
  return Grid::fromAffine(dims, a);
}

ScalarVolume volumeOf(const std::string& path, const Grid& g, const Matrix& m, const std::string& name) {
  if (m.values.size() != g.voxelCount())
    fail(path, "matrix '" + name + "' holds " + std::to_string(m.values.size()) + " values for " +
                   std::to_string(g.voxelCount()) + " voxels");
  ScalarVolume v(g, 1);
  v.data = m.values;
  return v;
}

bool wantSrc(const std::string& n) {
  return n == "dimension" || n == "voxel_size" || n == "b_table" || n.rfind("image", 0) == 0;
}
bool wantSrcHeader(const std::string& n) {
  return n == "dimension" || n == "voxel_size" || n == "b_table";
}
bool wantFib(const std::string& n) {
  return n == "dimension" || n == "voxel_size" || n == "odf_vertices" || n == "dti_fa" || n == "md" ||
         n == "ad" || n == "rd" || n.rfind("fa", 0) == 0 || n.rfind("index", 0) == 0;
}

void fillHeader(VolumeHeader& h, const std::string& path, const Grid& g, long long volumes) {
  h.path = path;
  h.niftiVersion = 0;
  h.dims = {g.dims.x, g.dims.y, g.dims.z};
  if (volumes > 1) h.dims.push_back(volumes);
  h.grid = g;
  h.datatypeName = "MATLAB v4";
  h.affineSource = "none in the file: DSI Studio's LPS voxel axes, centred";
  h.warnings.emplace_back("DSI Studio files carry no scanner position: LPS voxel axes assumed, centred on 0");
}

} // namespace

namespace detail {

VolumeHeader dsiHeader(const std::string& path) {
  const auto m = readMatlab4(path, wantSrcHeader);
  VolumeHeader h;
  const Grid g = dsiGrid(path, m);
  const Matrix& bt = need(path, m, "b_table");
  fillHeader(h, path, g, bt.cols);
  return h;
}

ScalarVolume readDsiSrcSignal(const std::string& path, VolumeHeader* header) {
  const auto m = readMatlab4(path, wantSrc);
  const Grid g = dsiGrid(path, m);
  const Matrix& bt = need(path, m, "b_table");
  if (bt.rows != 4 || bt.cols < 1)
    fail(path, "'b_table' is " + std::to_string(bt.rows) + "x" + std::to_string(bt.cols) + " (4xN expected)");
  const long long n = bt.cols;
  for (long long k = 0; k < n; ++k)
    need(path, m, "image" + std::to_string(k)); // every volume is there before anything is allocated
  if (n > detail::kMaxValues / static_cast<long long>(g.voxelCount()))
    fail(path, "b_table has " + std::to_string(n) + " columns: absurd for the grid; refusing to allocate");
  ScalarVolume v(g, static_cast<int>(n));
  const std::size_t nv = g.voxelCount();
  for (long long k = 0; k < n; ++k) {
    const std::string name = "image" + std::to_string(k);
    const Matrix& img = need(path, m, name);
    if (img.values.size() != nv)
      fail(path, "'" + name + "' holds " + std::to_string(img.values.size()) + " values for " +
                     std::to_string(nv) + " voxels");
    for (std::size_t i = 0; i < nv; ++i)
      v.data[i * static_cast<std::size_t>(n) + static_cast<std::size_t>(k)] = img.values[i];
  }
  if (header) {
    *header = VolumeHeader{};
    fillHeader(*header, path, g, n);
  }
  return v;
}

StoredGradients readDsiSrc(const std::string& path) {
  VolumeHeader h;
  StoredGradients out;
  out.signal = readDsiSrcSignal(path, &h);
  const auto m = readMatlab4(path, wantSrcHeader);
  const Matrix& bt = need(path, m, "b_table");
  // The b-table is in the voxel axes: the grid's rotation maps it to world.
  out.directionsToWorld = h.grid.rotation();
  for (long long c = 0; c < bt.cols; ++c) {
    const float* col = &bt.values[static_cast<std::size_t>(c * 4)];
    out.bvals.push_back(col[0]);
    out.directions.push_back(glm::dvec3(col[1], col[2], col[3]));
  }
  out.table = "b_table";
  return out;
}

} // namespace detail

DsiStudioFib readDsiStudioFib(const std::string& path) {
  const auto m = readMatlab4(path, wantFib);
  DsiStudioFib f;
  f.grid = dsiGrid(path, m);
  auto opt = [&](const char* name, ScalarVolume& out) {
    if (const auto it = m.find(name); it != m.end()) out = volumeOf(path, f.grid, it->second, name);
  };
  opt("dti_fa", f.dtiFa);
  opt("md", f.md);
  opt("ad", f.ad);
  opt("rd", f.rd);
  const Matrix& verts = need(path, m, "odf_vertices");
  if (verts.rows != 3 || verts.cols < 1) fail(path, "'odf_vertices' must be 3xN");
  const glm::dmat3 r = f.grid.rotation();
  const std::size_t nv = f.grid.voxelCount();
  for (int k = 0; k < 8; ++k) {
    const auto fa = m.find("fa" + std::to_string(k));
    const auto idx = m.find("index" + std::to_string(k));
    if (fa == m.end() || idx == m.end()) break;
    f.fraction.push_back(volumeOf(path, f.grid, fa->second, fa->first));
    const ScalarVolume index = volumeOf(path, f.grid, idx->second, idx->first);
    Volume<float> dir(f.grid, 3, 0.0f);
    for (std::size_t i = 0; i < nv; ++i) {
      if (!(f.fraction.back().data[i] > 0)) continue;
      const float x = index.data[i];
      if (!(x >= 0) || x >= static_cast<float>(verts.cols))
        fail(path, "index" + std::to_string(k) + " holds " + std::to_string(x) + ", outside odf_vertices (" +
                       std::to_string(verts.cols) + ")");
      const float* v = &verts.values[static_cast<std::size_t>(x) * 3];
      glm::dvec3 w = r * glm::dvec3(v[0], v[1], v[2]);
      const double len = glm::length(w);
      if (len > 0) w /= len;
      for (int c = 0; c < 3; ++c)
        dir.data[i * 3 + static_cast<std::size_t>(c)] = static_cast<float>(w[c]);
    }
    f.directions.push_back(std::move(dir));
  }
  if (f.fraction.empty()) fail(path, "has no fa0/index0 matrices (not a FIB file?)");
  return f;
}

} // namespace dtf::io
