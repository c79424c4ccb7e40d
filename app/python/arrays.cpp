// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/python/arrays.h"

#include "io/formats/format_detail.h"
#include "io/model/error.h"

#include <cmath>
#include <limits>

namespace dtf::python {

namespace {

// Offset of voxel (i, j, k) in a C-ordered (X, Y, Z, ...) array with `inner` values per voxel.
inline std::size_t cIndex(const glm::ivec3& d, int i, int j, int k, std::size_t inner) {
  return ((static_cast<std::size_t>(i) * d.y + j) * d.z + k) * inner;
}

std::vector<py::ssize_t> shape3(const Grid& g) {
  return {g.dims.x, g.dims.y, g.dims.z};
}

} // namespace

const std::vector<std::string>& arrayLayoutNames() {
  static const std::vector<std::string> names = {"auto",  "fsl",  "mrtrix", "symmatrix",
                                                 "dtitk", "dipy", "world"};
  return names;
}

io::LoadedTensors tensorsFromArray(const float* values, const glm::ivec3& dims, bool fiveD,
                                   const glm::dmat4& voxelToWorld, const std::string& layout,
                                   const std::string& name) {
  bool known = false;
  for (const std::string& n : arrayLayoutNames())
    known = known || n == layout;
  if (!known)
    throw UsageError("layout must be auto, fsl, mrtrix, symmatrix, dtitk, dipy or world, not '" + layout +
                     "'");
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(voxelToWorld[c][r]))
        throw InputError(name + ": the affine holds a NaN or infinite value");
  if (std::abs(glm::determinant(glm::dmat3(voxelToWorld))) < 1e-12)
    throw InputError(name + ": the affine is singular (its 3x3 part has determinant 0)");
  if (dims.x < 1 || dims.y < 1 || dims.z < 1) throw InputError(name + ": the array holds no voxel");

  io::LoadedTensors out;
  io::VolumeHeader& h = out.header;
  h.path = name;
  h.format = "numpy array";
  h.niftiVersion = 0;
  h.dims = {dims.x, dims.y, dims.z};
  if (fiveD) h.dims.push_back(1);
  h.dims.push_back(6);
  h.grid = Grid::fromAffine(dims, voxelToWorld);
  h.affineSource = "given";
  // A 5D array with 6 components is the SYMMATRIX shape; say so for detection as the NIfTI intent does.
  if (fiveD && layout == "auto") h.intentCode = 1005;

  // Components in the on-disk order of the layout the readers know; "world" is MRtrix's frame in the
  // canonical order, "dipy" is symmatrix.
  io::TensorLayout l = io::TensorLayout::Auto;
  if (layout == "world" || layout == "mrtrix")
    l = io::TensorLayout::Mrtrix;
  else if (layout == "dipy" || layout == "symmatrix")
    l = io::TensorLayout::Symmatrix;
  else if (layout != "auto")
    l = io::parseLayout(layout);
  static constexpr int kWorldToMrtrix[6] = {0, 3, 5, 1, 2, 4}; // mrtrix slot n holds canonical component
  ScalarVolume raw(h.grid, 6);
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const float* src = values + cIndex(dims, i, j, k, 6);
        float* dst = &raw.data[h.grid.index(i, j, k) * 6];
        for (int c = 0; c < 6; ++c)
          dst[c] = layout == "world" ? src[kWorldToMrtrix[c]] : src[c];
      }
  io::detail::tensorsFromComponents(out, raw, l, fiveD, name, io::TensorLayout::Fsl);
  if (layout == "world") out.layoutReason = "given explicitly (world: xx xy xz yy yz zz in world RAS)";
  if (layout == "dipy")
    out.layoutReason =
        "given explicitly (dipy: lower triangle xx xy yy xz yz zz in the gradient table's frame, "
        "as symmatrix)";
  return out;
}

glm::dmat4 affineFromPython(const py::handle& affine, const std::string& name) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(affine);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || !((a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) ||
              (a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 4)))
    throw InputError(name + ": the affine must be a 4x4 (or 3x4) array of numbers");
  glm::dmat4 m(1.0);
  auto v = a.unchecked<2>();
  for (py::ssize_t r = 0; r < a.shape(0); ++r)
    for (int c = 0; c < 4; ++c)
      m[c][static_cast<int>(r)] = v(r, c);
  return m;
}

py::array_t<double> affineArray(const Grid& grid) {
  py::array_t<double> a({4, 4});
  auto v = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      v(r, c) = grid.voxelToWorld[c][r];
  return a;
}

py::array_t<float> tensorArray(const TensorField& field) {
  const Grid& g = field.grid;
  std::vector<py::ssize_t> shape = shape3(g);
  shape.push_back(6);
  py::array_t<float> a(shape);
  float* out = a.mutable_data();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        const std::size_t idx = g.index(i, j, k);
        float* dst = out + cIndex(g.dims, i, j, k, 6);
        const SymTensor& t = field.tensors[idx];
        const double c[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
        for (int n = 0; n < 6; ++n)
          dst[n] = field.valid[idx] ? static_cast<float>(c[n]) : nan;
      }
  return a;
}

py::array_t<float> scalarArray(const ScalarVolume& v) {
  const Grid& g = v.grid;
  std::vector<py::ssize_t> shape = shape3(g);
  if (v.components > 1) shape.push_back(v.components);
  py::array_t<float> a(shape);
  float* out = a.mutable_data();
  const auto nc = static_cast<std::size_t>(v.components);
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i)
        for (std::size_t c = 0; c < nc; ++c)
          out[cIndex(g.dims, i, j, k, nc) + c] = v.data[g.index(i, j, k) * nc + c];
  return a;
}

py::array_t<float> fibreDirections(const FibreSet& set) {
  const Grid& g = set.grid;
  const auto kk = static_cast<std::size_t>(set.maxFibres);
  std::vector<py::ssize_t> shape = shape3(g);
  shape.push_back(set.maxFibres);
  shape.push_back(3);
  py::array_t<float> a(shape);
  float* out = a.mutable_data();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        const Fibre* f = set.at(i, j, k);
        float* dst = out + cIndex(g.dims, i, j, k, kk * 3);
        for (std::size_t n = 0; n < kk; ++n)
          for (int c = 0; c < 3; ++c)
            dst[n * 3 + c] = f[n].amplitude > 0 ? f[n].direction[c] : nan;
      }
  return a;
}

py::array_t<float> fibreAmplitudes(const FibreSet& set) {
  const Grid& g = set.grid;
  const auto kk = static_cast<std::size_t>(set.maxFibres);
  std::vector<py::ssize_t> shape = shape3(g);
  shape.push_back(set.maxFibres);
  py::array_t<float> a(shape);
  float* out = a.mutable_data();
  for (int k = 0; k < g.dims.z; ++k)
    for (int j = 0; j < g.dims.y; ++j)
      for (int i = 0; i < g.dims.x; ++i) {
        const Fibre* f = set.at(i, j, k);
        float* dst = out + cIndex(g.dims, i, j, k, kk);
        for (std::size_t n = 0; n < kk; ++n)
          dst[n] = f[n].amplitude > 0 ? f[n].amplitude : 0.0f;
      }
  return a;
}

py::array_t<std::uint8_t> imageArray(const Image& image) {
  py::array_t<std::uint8_t> a({image.height, image.width, 4});
  std::copy(image.rgba.begin(), image.rgba.end(), a.mutable_data());
  return a;
}

std::string pathText(const py::handle& p) {
  const py::object os = py::module_::import("os");
  const std::string s = py::str(os.attr("fsdecode")(os.attr("fspath")(p)));
  if (s.find('\0') != std::string::npos)
    throw UsageError("the path " + std::string(py::str(py::repr(p))) + " contains a NUL character");
  return s;
}

std::string optionalPath(const py::object& p) {
  return p.is_none() ? std::string() : pathText(p);
}

} // namespace dtf::python
