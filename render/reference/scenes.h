// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic inputs for the render tests and benchmarks: analytic tensor fields (constant direction,
// crossing, the Hessians of the sphere and Bretzel5 implicit functions of paper §3.1) and simple meshes
// (planes, UV spheres, marching-tetrahedra isosurfaces). All in world RAS mm, canonical tensor form.
#pragma once

#include "io/model/geometry.h"
#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <functional>

namespace dtf::render::reference {

// A cubic grid of n^3 voxels of `spacing` mm centred on the origin (identity rotation).
Grid centredGrid(int n, double spacing);
// Linear tensors lambda1 d d^T + lambda2 (I - d d^T), d unit.
TensorField constantField(const Grid& grid, const glm::dvec3& direction, double lambda1 = 1.7e-3,
                          double lambda2 = 0.3e-3);
// Two bundles: weight a on direction da, (1 - a) on db (linear tensors as above, summed).
TensorField crossingField(const Grid& grid, const glm::dvec3& da, const glm::dvec3& db, double a = 0.6);
// Hessian of f(x) evaluated per voxel by central differences of step h (mm).
TensorField hessianField(const Grid& grid, const std::function<double(const glm::dvec3&)>& f, double h);
// Sphere: f = |x|^2 + c x y z with c = 1.5 / radius, so the Hessian is anisotropic on the sphere.
double sphereFunction(const glm::dvec3& p, double radius);
// Bretzel5 (paper Eq. 14), coordinates scaled by 1/scale: ((x^2 + y^2/4 - 1)(x^2/4 + y^2 - 1))^2 + z^2 - 0.1.
double bretzel5Function(const glm::dvec3& p, double scale);
// Samples f on the grid's voxel centres.
ScalarVolume sampleFunction(const Grid& grid, const std::function<double(const glm::dvec3&)>& f);

// A plane through `centre` spanned by unit u and v, size su x sv mm, n x n quads; normal u x v.
Mesh planeMesh(const glm::dvec3& centre, const glm::dvec3& u, const glm::dvec3& v, double su, double sv, int n);
// UV sphere with `rings` latitude bands and `segments` longitudes: 2 * segments * (rings - 1) triangles.
Mesh uvSphere(const glm::dvec3& centre, double radius, int rings, int segments);
// Isosurface of a scalar volume by marching tetrahedra, normals from the volume gradient pointing to
// increasing values (outward for the implicit functions above).
Mesh marchingTetrahedra(const ScalarVolume& v, double iso);

} // namespace dtf::render::reference
