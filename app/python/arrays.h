// SPDX-License-Identifier: GPL-3.0-or-later
// numpy in and out for the Python module: the canonical tensor field as a (X, Y, Z, 6) float32 array (world
// RAS, xx xy xz yy yz zz, mm^2/s, NaN where invalid), affines as 4x4 float64 arrays, and tensor fields made
// from arrays in any on-disk layout through the readers' own conversion (io::detail::tensorsFromComponents),
// so an array and the file it came from give the same field.
#pragma once

#include "io/formats/fibre_io.h"
#include "io/model/geometry.h"
#include "io/model/image.h"
#include "io/formats/tensor_io.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <string>
#include <vector>

namespace dtf::python {

namespace py = pybind11;

// Layout names an array may be given in: the readers' (auto, fsl, mrtrix, symmatrix, dtitk), "dipy" (DIPY's
// TensorFit.lower_triangular(): xx xy yy xz yz zz in the frame of its gradient table, as symmatrix) and
// "world" (the canonical order xx xy xz yy yz zz in world RAS, what TensorField.tensor holds).
const std::vector<std::string>& arrayLayoutNames();

// A tensor field from C-ordered float32 values of shape dims[0..2] x 6 (or x 1 x 6 when fiveD) in `layout`,
// on the grid of `voxelToWorld`. `name` starts every error message. Throws InputError (NaN or singular
// affine, every voxel NaN) or UsageError (unknown layout). Call without the GIL.
io::LoadedTensors tensorsFromArray(const float* values, const glm::ivec3& dims, bool fiveD,
                                   const glm::dmat4& voxelToWorld, const std::string& layout,
                                   const std::string& name);

// A 4x4 affine from any array-like (Python side). Throws InputError naming `name` for a wrong shape.
glm::dmat4 affineFromPython(const py::handle& affine, const std::string& name);

py::array_t<double> affineArray(const Grid& grid);
py::array_t<float> tensorArray(const TensorField& field);
py::array_t<float> scalarArray(const ScalarVolume& volume); // (X, Y, Z) or (X, Y, Z, C)
// Directions (X, Y, Z, K, 3), NaN where absent; amplitudes (X, Y, Z, K), 0 where absent.
py::array_t<float> fibreDirections(const FibreSet& set);
py::array_t<float> fibreAmplitudes(const FibreSet& set);
py::array_t<std::uint8_t> imageArray(const Image& image); // (H, W, 4)

// A path argument as the library takes it: str, bytes or os.PathLike (bytes decoded as os.fsdecode does, so
// a name in the file system's encoding round-trips). A NUL character cannot be in a path (UsageError), as
// Python's open() refuses it too. optionalPath: "" for None.
std::string pathText(const py::handle& p);
std::string optionalPath(const py::object& p);

// The tract functions (app/python/tracts.cpp): select.
void bindTracts(py::module_& m);

} // namespace dtf::python
