// Raw diffusion-weighted images with their b-values and gradient directions, and the tensor fit.
#pragma once

#include "io/model/tensor_field.h"
#include "io/model/volume.h"

#include <functional>
#include <string>
#include <vector>

namespace dtf::io {

struct Dwi {
  Volume<float> signal;                 // components = number of volumes (interleaved per voxel)
  std::vector<double> bvals;            // s/mm^2
  std::vector<glm::dvec3> gradientsWorld; // unit gradient directions rotated into world RAS (zero for b=0)
  std::string path;
};

// Reads bval (one row) and bvec (FSL 3xN or Nx3; NaN rows for b=0 allowed) files.
std::vector<double> readBvals(const std::string& path);
std::vector<glm::dvec3> readBvecs(const std::string& path, std::size_t expectedCount);
// Reads a 4D DWI and its gradient table; bvecs in FSL's frame are rotated into world space.
Dwi readDwi(const std::string& dwiPath, const std::string& bvalPath, const std::string& bvecPath);

enum class FitMethod { Wls, Ols };

struct FitOptions {
  FitMethod method = FitMethod::Wls;
  double b0Threshold = 50.0; // b-values at or below this count as b=0 (s/mm^2)
  int threads = 0;           // 0 = hardware concurrency
};

using ProgressFn = std::function<void(double fraction)>;

// Fits a tensor per voxel inside `mask` (automatic brain mask when null). Result is canonical.
TensorField fitTensors(const Dwi& dwi, const MaskVolume* mask, const FitOptions& options,
                       const ProgressFn& progress = {});
// Simple automatic brain mask from the mean b=0 image (Otsu threshold, largest component, hole filling).
MaskVolume automaticMask(const Dwi& dwi, double b0Threshold);

} // namespace dtf::io
