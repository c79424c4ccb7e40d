#include "surfaces/isosurface.h"

#include "surfaces/detail/vtk_convert.h"

#include <vtkCleanPolyData.h>
#include <vtkFlyingEdges3D.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkImageGaussianSmooth.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyDataConnectivityFilter.h>
#include <vtkPolyDataNormals.h>
#include <vtkWindowedSincPolyDataFilter.h>

#include <algorithm>

namespace dtf::surfaces {

Mesh extractIsosurface(const ScalarVolume& volume, double isovalue, const IsosurfaceOptions& options) {
  const glm::ivec3 d = volume.grid.dims;
  if (d.x < 2 || d.y < 2 || d.z < 2) return {};
  // Extract in voxel-index space (origin 0, spacing 1) and map to world afterwards: VTK's filters ignore
  // an image's direction matrix, and this keeps oblique and LAS affines exact.
  vtkNew<vtkImageData> image;
  image->SetDimensions(d.x, d.y, d.z);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfTuples(static_cast<vtkIdType>(volume.grid.voxelCount()));
  for (std::size_t i = 0; i < volume.grid.voxelCount(); ++i)
    scalars->SetValue(static_cast<vtkIdType>(i), volume.data[i * volume.components]);
  image->GetPointData()->SetScalars(scalars);

  vtkNew<vtkFlyingEdges3D> contour;
  vtkNew<vtkImageGaussianSmooth> smooth;
  if (options.smoothSigmaVoxels > 0) {
    smooth->SetInputData(image);
    smooth->SetStandardDeviations(options.smoothSigmaVoxels, options.smoothSigmaVoxels, options.smoothSigmaVoxels);
    smooth->SetRadiusFactors(2.5, 2.5, 2.5);
    contour->SetInputConnection(smooth->GetOutputPort());
  } else {
    contour->SetInputData(image);
  }
  contour->SetValue(0, isovalue);
  contour->ComputeNormalsOn(); // from the volume gradient: smoother than face normals
  contour->ComputeScalarsOff();
  contour->ComputeGradientsOff();
  contour->Update();
  vtkSmartPointer<vtkPolyData> poly = contour->GetOutput();
  if (!poly || poly->GetNumberOfCells() == 0) return {};

  if (options.minComponentFraction > 0) {
    vtkNew<vtkPolyDataConnectivityFilter> conn;
    conn->SetInputData(poly);
    conn->SetExtractionModeToAllRegions();
    conn->Update();
    vtkIdTypeArray* sizes = conn->GetRegionSizes();
    vtkIdType largest = 0;
    for (vtkIdType r = 0; r < sizes->GetNumberOfTuples(); ++r) largest = std::max(largest, sizes->GetValue(r));
    vtkNew<vtkPolyDataConnectivityFilter> keep;
    keep->SetInputData(poly);
    keep->SetExtractionModeToSpecifiedRegions();
    for (vtkIdType r = 0; r < sizes->GetNumberOfTuples(); ++r)
      if (static_cast<double>(sizes->GetValue(r)) >= options.minComponentFraction * static_cast<double>(largest))
        keep->AddSpecifiedRegion(static_cast<int>(r));
    // The connectivity filter keeps every input point; drop the ones no kept triangle uses.
    vtkNew<vtkCleanPolyData> clean;
    clean->SetInputConnection(keep->GetOutputPort());
    clean->PointMergingOff();
    clean->Update();
    poly = clean->GetOutput();
  }
  if (options.meshSmoothIterations > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> sinc;
    sinc->SetInputData(poly);
    sinc->SetNumberOfIterations(options.meshSmoothIterations);
    sinc->SetPassBand(0.1);
    sinc->NormalizeCoordinatesOn();
    sinc->BoundarySmoothingOff();
    sinc->FeatureEdgeSmoothingOff();
    sinc->NonManifoldSmoothingOn();
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputConnection(sinc->GetOutputPort());
    normals->SplittingOff();
    normals->ConsistencyOn();
    normals->AutoOrientNormalsOff();
    normals->Update();
    poly = normals->GetOutput();
  }

  Mesh m = detail::fromVtk(poly);
  // Map index space to world: positions by the affine, normals by its inverse transpose. A reflecting
  // affine (LAS) reverses the triangles' winding, so swap two indices to keep counter-clockwise = front.
  const glm::dmat4& a = volume.grid.voxelToWorld;
  const glm::dmat3 nmat = glm::transpose(glm::inverse(glm::dmat3(a)));
  for (auto& p : m.positions) p = glm::vec3(a * glm::dvec4(glm::dvec3(p), 1.0));
  const float sign = options.flipNormals ? -1.0f : 1.0f;
  for (auto& n : m.normals) {
    glm::vec3 w = glm::vec3(nmat * glm::dvec3(n));
    float l = glm::length(w);
    n = sign * (l > 0 ? w / l : glm::vec3(0, 0, 1));
  }
  bool flipWinding = glm::determinant(glm::dmat3(a)) < 0;
  if (options.flipNormals) flipWinding = !flipWinding;
  if (flipWinding)
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
  return m;
}

} // namespace dtf::surfaces
