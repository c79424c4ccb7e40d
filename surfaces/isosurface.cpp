// SPDX-License-Identifier: GPL-3.0-or-later
#include "surfaces/isosurface.h"

#include "io/model/error.h"
#include "surfaces/detail/vtk_convert.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkImageGaussianSmooth.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataNormals.h>
#include <vtkWindowedSincPolyDataFilter.h>

namespace dtf::surfaces {

namespace {
std::string shortNumber(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}
} // namespace

struct IsosurfaceSweeper::Impl {
  vtkSmartPointer<vtkImageData> image; // prepared volume, index space (padded by one voxel when closing)
  glm::dmat4 voxelToWorld{1.0};
  IsosurfaceOptions options;
};

IsosurfaceSweeper::IsosurfaceSweeper(const ScalarVolume& volume, const IsosurfaceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!(options.smoothSigmaVoxels >= 0 && options.smoothSigmaVoxels <= kMaxSmoothSigmaVoxels))
    throw UsageError("the pre-smoothing sigma " + shortNumber(options.smoothSigmaVoxels) +
                     " voxels is outside 0.." + std::to_string(int(kMaxSmoothSigmaVoxels)));
  if (!(options.minComponentFraction >= 0 && options.minComponentFraction <= 1))
    throw UsageError("the smallest component's fraction " + shortNumber(options.minComponentFraction) +
                     " is outside 0..1");
  if (!(options.maxShiftVoxels >= 0) || !std::isfinite(options.maxShiftVoxels))
    throw UsageError("the largest smoothing shift " + shortNumber(options.maxShiftVoxels) +
                     " voxels is not a finite number >= 0");
  impl_->options = options;
  impl_->options.mask = nullptr; // only used here
  impl_->voxelToWorld = volume.grid.voxelToWorld;
  const glm::ivec3 d = volume.grid.dims;
  const std::size_t n = volume.grid.voxelCount();
  if (d.x < 2 || d.y < 2 || d.z < 2) return;
  if (options.mask && options.mask->grid.dims != d)
    throw InputError("isosurface mask and volume have different dimensions");
  // The outside value: the minimum when the object holds high values, else the maximum.
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (std::size_t i = 0; i < n; ++i) {
    float v = volume.data[i * volume.components];
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (lo > hi) lo = hi = 0;
  const float outside = options.insideIsLow ? hi : lo;
  // Extract in voxel-index space and map to world afterwards: VTK's filters ignore an image's direction
  // matrix, and this keeps oblique and LAS affines exact. Padding sits at index -1 and d.
  const int pad = options.closeAtBorder ? 1 : 0;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(d.x + 2 * pad, d.y + 2 * pad, d.z + 2 * pad);
  image->SetOrigin(-pad, -pad, -pad);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfTuples(image->GetNumberOfPoints());
  scalars->FillValue(outside);
  for (int k = 0; k < d.z; ++k)
    for (int j = 0; j < d.y; ++j)
      for (int i = 0; i < d.x; ++i) {
        std::size_t src = volume.grid.index(i, j, k);
        float v = volume.data[src * volume.components];
        if (!std::isfinite(v) || (options.mask && options.mask->data[src] == 0)) v = outside;
        vtkIdType dst = (i + pad) + static_cast<vtkIdType>(d.x + 2 * pad) *
                                        ((j + pad) + static_cast<vtkIdType>(d.y + 2 * pad) * (k + pad));
        scalars->SetValue(dst, v);
      }
  image->GetPointData()->SetScalars(scalars);
  if (options.smoothSigmaVoxels > 0) {
    vtkNew<vtkImageGaussianSmooth> smooth;
    smooth->SetInputData(image);
    const double s = options.smoothSigmaVoxels;
    smooth->SetStandardDeviations(s, s, s);
    smooth->SetRadiusFactors(2.5, 2.5, 2.5);
    smooth->Update();
    image = smooth->GetOutput();
  }
  impl_->image = image;
}

IsosurfaceSweeper::~IsosurfaceSweeper() = default;
IsosurfaceSweeper::IsosurfaceSweeper(IsosurfaceSweeper&&) noexcept = default;
IsosurfaceSweeper& IsosurfaceSweeper::operator=(IsosurfaceSweeper&&) noexcept = default;

Mesh IsosurfaceSweeper::extract(double isovalue, SmoothingReport* report) const {
  if (!impl_ || !impl_->image) return {};
  const IsosurfaceOptions& options = impl_->options;
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(impl_->image);
  contour->SetValue(0, isovalue);
  contour->ComputeNormalsOn(); // from the volume gradient: smoother than face normals
  contour->ComputeScalarsOff();
  contour->ComputeGradientsOff();
  contour->Update();
  vtkSmartPointer<vtkPolyData> poly = contour->GetOutput();
  if (!poly || poly->GetNumberOfCells() == 0) return {};

  if (options.meshSmoothIterations > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> sinc;
    sinc->SetInputData(poly);
    sinc->SetNumberOfIterations(options.meshSmoothIterations);
    sinc->SetPassBand(0.1);
    sinc->NormalizeCoordinatesOn();
    sinc->BoundarySmoothingOff();
    sinc->FeatureEdgeSmoothingOff();
    sinc->NonManifoldSmoothingOn();
    sinc->Update();
    vtkSmartPointer<vtkPolyData> smoothed = sinc->GetOutput();
    // The filter keeps the points' order: bound each vertex's shift (index space = voxels).
    vtkPoints* before = poly->GetPoints();
    vtkPoints* after = smoothed->GetPoints();
    SmoothingReport r;
    if (before && after && before->GetNumberOfPoints() == after->GetNumberOfPoints()) {
      const double limit = std::max(options.maxShiftVoxels, 0.0);
      double sum = 0;
      r.vertices = static_cast<std::size_t>(after->GetNumberOfPoints());
      for (vtkIdType i = 0; i < after->GetNumberOfPoints(); ++i) {
        double a[3], b[3];
        before->GetPoint(i, a);
        after->GetPoint(i, b);
        glm::dvec3 d(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        const double len = glm::length(d);
        r.maxShiftVoxels = std::max(r.maxShiftVoxels, len);
        if (len > limit) {
          d *= limit / len;
          after->SetPoint(i, a[0] + d.x, a[1] + d.y, a[2] + d.z);
          ++r.clamped;
        }
        sum += std::min(len, limit);
      }
      r.meanShiftVoxels = r.vertices ? sum / static_cast<double>(r.vertices) : 0.0;
      after->Modified();
    }
    if (report) *report = r;
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputData(smoothed);
    normals->SplittingOff();
    normals->ConsistencyOn();
    normals->AutoOrientNormalsOff();
    normals->Update();
    poly = normals->GetOutput();
  }

  Mesh m = detail::fromVtk(poly);
  if (options.minComponentFraction > 0) detail::keepLargeComponents(m, options.minComponentFraction);
  // Map index space to world: positions by the affine, normals by its inverse transpose. A reflecting
  // affine (LAS) reverses the triangles' winding, so swap two indices to keep counter-clockwise = front.
  const glm::dmat4& a = impl_->voxelToWorld;
  const glm::dmat3 nmat = glm::transpose(glm::inverse(glm::dmat3(a)));
  for (auto& p : m.positions) p = glm::vec3(a * glm::dvec4(glm::dvec3(p), 1.0));
  // VTK's gradient normals point towards lower values: out of a high-valued object.
  const float sign = options.insideIsLow ? -1.0f : 1.0f;
  for (auto& nrm : m.normals) {
    glm::vec3 w = glm::vec3(nmat * glm::dvec3(nrm));
    float l = glm::length(w);
    nrm = sign * (l > 0 ? w / l : glm::vec3(0, 0, 1));
  }
  bool flipWinding = glm::determinant(glm::dmat3(a)) < 0;
  if (options.insideIsLow) flipWinding = !flipWinding;
  if (flipWinding)
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
  return m;
}

Mesh extractIsosurface(const ScalarVolume& volume, double isovalue, const IsosurfaceOptions& options,
                       SmoothingReport* report) {
  return IsosurfaceSweeper(volume, options).extract(isovalue, report);
}

} // namespace dtf::surfaces
