// SPDX-License-Identifier: GPL-3.0-or-later
// Symmetric 3x3 diffusion tensors and their metrics. Canonical component order is xx, xy, xz, yy, yz, zz
// in world RAS, units mm^2/s (see TensorField). The closed-form eigen-solver here is the CPU reference
// for the GLSL solver in shaders/common/eigen.glsl and handles repeated eigenvalues, diagonal and zero
// tensors without NaN.
#pragma once

#include <glm/glm.hpp>

#include <array>

namespace dtf {

struct SymTensor {
  float xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;

  static SymTensor fromMat(const glm::dmat3& m);
  glm::dmat3 toMat() const;
  bool isFinite() const;
  bool isZero() const { return xx == 0 && xy == 0 && xz == 0 && yy == 0 && yz == 0 && zz == 0; }
  std::array<float, 6> components() const { return {xx, xy, xz, yy, yz, zz}; }
};

// Eigen-decomposition: values descending, vectors[i] the unit eigenvector of values[i] (right-handed set).
struct EigenSystem {
  glm::dvec3 values{0.0};
  std::array<glm::dvec3, 3> vectors{glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
};

// Closed-form decomposition (trigonometric eigenvalues, cross-product / 2x2 sub-problem eigenvectors).
// Always returns finite, orthonormal vectors; for repeated eigenvalues any orthonormal basis of the
// eigenspace is returned.
EigenSystem eigenDecompose(const glm::dmat3& symmetric);
inline EigenSystem eigenDecompose(const SymTensor& t) { return eigenDecompose(t.toMat()); }

struct TensorMetrics {
  double fa = 0;   // fractional anisotropy, clamped to [0, 1]
  double md = 0;   // mean diffusivity, mm^2/s
  double ad = 0;   // axial diffusivity (largest eigenvalue), mm^2/s
  double rd = 0;   // radial diffusivity (mean of the two smaller), mm^2/s
  double mode = 0; // tensor mode in [-1, 1] (Ennis & Kindlmann 2006); 0 for isotropic tensors
};

TensorMetrics computeMetrics(const EigenSystem& e);
double fractionalAnisotropy(const glm::dvec3& eigenvalues);
// The same from the tensor's invariants, without an eigen-decomposition:
// FA = sqrt(3/2) |D - tr(D)/3 I|_F / |D|_F (the hot path of FA maps).
double fractionalAnisotropy(const SymTensor& t);
// Tensor mode from the deviatoric part: 3*sqrt(6)*det(D~/|D~|).
double tensorMode(const glm::dmat3& d);
// Directionally encoded colour: |e1| (x red, y green, z blue) scaled by FA, each channel in [0, 1].
glm::dvec3 decColor(const EigenSystem& e, double fa);

// Rotates a tensor: R T R^T (R maps the tensor's frame to the target frame).
SymTensor rotateTensor(const SymTensor& t, const glm::dmat3& r);

} // namespace dtf
