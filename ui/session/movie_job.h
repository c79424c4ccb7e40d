// SPDX-License-Identifier: GPL-3.0-or-later
// Movies of the fabric, as `dtfabric movie` and dtfabric.movie (Python) make them: a turntable around the
// surface, a sweep of slices through the volume, or an FA-threshold sweep (the isosurface extracted again per
// frame). The camera and the surface change from frame to frame while the advection state is carried over
// (render::FabricRenderer::renderMovieFrame: the previous frame's state reprojected, then a few Eq. 12
// iterations, as the paper's interactive mode runs), so the threads stay put instead of flickering.
#pragma once

#include "ui/session/render_job.h"
#include "render/camera.h"

#include <functional>
#include <string>
#include <vector>

namespace dtf::session {

struct MovieRequest {
  RenderRequest render; // input, surface, view (turntable default: anterior), size, fabric parameters, background
  enum class Kind { Turntable, Sweep, FaSweep } kind = Kind::Turntable;
  std::string axis = "axial";     // Sweep: axial|coronal|sagittal, through the slices that hold data
  double faLo = 0.15, faHi = 0.5; // FaSweep: thresholds of the first and the last frame
  int frames = 36;
  double elevationDeg = 20; // Turntable: camera height above the horizontal plane of the view
};

// The frames' cameras of a turntable: a full turn about the world superior axis through the centre of
// [lo, hi], starting from `start` (its view direction, raised by `elevationDeg`), framed so the box's bounding
// sphere stays inside the image at every angle. Frame i is at 360 i / frames degrees.
std::vector<render::Camera> turntableCameras(render::StandardView start, const glm::dvec3& lo, const glm::dvec3& hi,
                                             double aspect, int frames, double elevationDeg, bool neurological,
                                             bool orthographic);

// `camera` turned by `degrees` about the unit `axis` through its target (eye and up; right-handed).
render::Camera turnedAbout(const render::Camera& camera, const glm::dvec3& axis, double degrees);

// Slice indices of a sweep: `frames` indices from the first to the last slice along `axis` holding data
// (FA > 0) in at least kSweepSliceFraction of the voxels of the fullest slice, evenly spaced (repeating
// indices when frames exceed the slices).
constexpr double kSweepSliceFraction = 0.05;
std::vector<int> sweepIndices(const ScalarVolume& fa, const std::string& axis, int frames);

// The same through the slices holding data: FA > 0, or where there is no FA (a fibre set without a paired
// tensor) the valid voxels of `field` (the fibres' carrier).
std::vector<int> sweepIndices(const ScalarVolume& fa, const TensorField& field, const std::string& axis,
                              int frames);
// The surface of frame `i` of `frames` of an FA sweep from lo to hi, and of a slice sweep.
SurfaceSpec faSweepSpec(double lo, double hi, int i, int frames);
SurfaceSpec sliceSweepSpec(const std::string& axis, int index);

// Renders the frames in order and hands each to `sink(index, image)`; `progress(done, total)` after each.
// Throws as runRender; UsageError for a bad kind, range or frame count.
void runMovie(const MovieRequest& request, const std::function<void(int, const Image&)>& sink,
              const std::function<void(int, int)>& progress = {});

} // namespace dtf::session
