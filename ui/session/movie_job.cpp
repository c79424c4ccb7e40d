// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/movie_job.h"

#include "io/model/error.h"
#include "surfaces/slices.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace dtf::session {

namespace {

// Rotates v about the unit axis a by `angle` radians (Rodrigues).
glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(a, v) * s + a * glm::dot(a, v) * (1 - c);
}

SurfaceSpec sliceSpec(const std::string& axis, int index) {
  return parseSurfaceSpec("slice=" + axis + ":" + std::to_string(index));
}

SurfaceSpec faSpec(double t) {
  std::ostringstream o;
  o.precision(6);
  o << "fa=" << t;
  return parseSurfaceSpec(o.str());
}

double faAt(const MovieRequest& r, int i) {
  return r.frames > 1 ? r.faLo + (r.faHi - r.faLo) * i / (r.frames - 1) : r.faLo;
}

void validate(const MovieRequest& r) {
  if (r.frames < 1 || r.frames > 10000) throw UsageError("--frames must be in [1, 10000]");
  if (r.kind == MovieRequest::Kind::FaSweep &&
      !(r.faLo > 0 && r.faLo < 1 && r.faHi > 0 && r.faHi < 1 && r.faLo != r.faHi))
    throw UsageError("--fa-sweep LO:HI needs two different FA thresholds in (0, 1)");
  if (!(std::abs(r.elevationDeg) <= 89)) throw UsageError("--elevation must be in [-89, 89] degrees");
}

} // namespace

render::Camera turnedAbout(const render::Camera& camera, const glm::dvec3& axis, double degrees) {
  const double a = glm::radians(degrees);
  render::Camera c = camera;
  c.lookAt(camera.target + rotate(camera.eye - camera.target, axis, a), camera.target, rotate(camera.up, axis, a));
  return c;
}

std::vector<render::Camera> turntableCameras(render::StandardView start, const glm::dvec3& lo, const glm::dvec3& hi,
                                             double aspect, int frames, double elevationDeg, bool neurological,
                                             bool orthographic) {
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-3);
  const glm::dvec3 half(radius);
  render::Camera c0 = render::Camera::standard(start, centre - half, centre + half, aspect, neurological, orthographic);
  // Raise the camera about its right axis.
  const double e = glm::radians(elevationDeg);
  const glm::dvec3 right = c0.right();
  const glm::dvec3 d = rotate(c0.eye - c0.target, right, -e);
  const glm::dvec3 up = rotate(c0.up, right, -e);
  std::vector<render::Camera> cams;
  cams.reserve(static_cast<std::size_t>(std::max(frames, 0)));
  render::Camera raised = c0;
  raised.lookAt(c0.target + d, c0.target, up);
  for (int i = 0; i < frames; ++i) cams.push_back(turnedAbout(raised, glm::dvec3(0, 0, 1), 360.0 * i / frames));
  return cams;
}

std::vector<int> sweepIndices(const ScalarVolume& fa, const std::string& axis, int frames) {
  const surfaces::SliceAxis a = surfaces::parseSliceAxis(axis);
  const int va = surfaces::voxelAxisFor(fa.grid, a);
  const glm::ivec3 dims = fa.grid.dims;
  std::vector<std::size_t> held(static_cast<std::size_t>(dims[va]), 0); // voxels with data per slice
  for (int k = 0; k < dims.z; ++k)
    for (int j = 0; j < dims.y; ++j)
      for (int i = 0; i < dims.x; ++i) {
        const std::size_t v = (static_cast<std::size_t>(k) * dims.y + j) * dims.x + i;
        if (fa.data[v * static_cast<std::size_t>(fa.components)] > 0)
          ++held[static_cast<std::size_t>(glm::ivec3(i, j, k)[va])];
      }
  const std::size_t most = held.empty() ? 0 : *std::max_element(held.begin(), held.end());
  if (most == 0) throw InputError("the data holds no voxel with FA > 0 to sweep through");
  // The end slices of an automatic mask hold a few scattered noise voxels: a sweep that starts there
  // shows an empty frame. A slice counts once it holds kSweepSliceFraction of the fullest slice's data.
  const std::size_t enough =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(kSweepSliceFraction * most)));
  int first = 0, last = dims[va] - 1;
  while (held[static_cast<std::size_t>(first)] < enough)
    ++first;
  while (held[static_cast<std::size_t>(last)] < enough)
    --last;
  std::vector<int> out;
  for (int f = 0; f < frames; ++f)
    out.push_back(frames > 1 ? first + static_cast<int>(std::lround(double(last - first) * f / (frames - 1)))
                             : (first + last) / 2);
  return out;
}

SurfaceSpec faSweepSpec(double lo, double hi, int i, int frames) {
  return faSpec(frames > 1 ? lo + (hi - lo) * i / (frames - 1) : lo);
}

SurfaceSpec sliceSweepSpec(const std::string& axis, int index) {
  return sliceSpec(axis, index);
}

std::vector<int> sweepIndices(const ScalarVolume& fa, const TensorField& field, const std::string& axis,
                              int frames) {
  if (std::any_of(fa.data.begin(), fa.data.end(), [](float v) { return v > 0; }))
    return sweepIndices(fa, axis, frames);
  ScalarVolume occupied(field.grid, 1);
  for (std::size_t v = 0; v < occupied.data.size() && v < field.valid.size(); ++v)
    occupied.data[v] = field.valid[v] ? 1.0f : 0.0f;
  return sweepIndices(occupied, axis, frames);
}

void runMovie(const MovieRequest& request, const std::function<void(int, const Image&)>& sink,
              const std::function<void(int, int)>& progress) {
  validate(request);
  MovieRequest r = request;
  if (r.kind == MovieRequest::Kind::FaSweep) r.render.surface = faSpec(r.faLo);
  if (r.kind == MovieRequest::Kind::Sweep) {
    surfaces::parseSliceAxis(r.axis); // validates
    r.render.surface = parseSurfaceSpec("slice=" + r.axis);
  }
  FrameSession session(r.render);
  const double aspect = double(r.render.width) / r.render.height;
  const bool ortho = !r.render.perspective, neuro = r.render.neurological;
  const auto done = [&](int i, const Image& img) {
    sink(i, img);
    if (progress) progress(i + 1, r.frames);
  };

  if (r.kind == MovieRequest::Kind::Turntable) {
    glm::vec3 lo, hi;
    session.surface().bounds(lo, hi);
    const auto cams = turntableCameras(r.render.view ? *r.render.view : render::StandardView::Anterior,
                                       glm::dvec3(lo), glm::dvec3(hi), aspect, r.frames, r.elevationDeg, neuro, ortho);
    for (int i = 0; i < r.frames; ++i) done(i, session.frame(cams[static_cast<std::size_t>(i)], i == 0));
    return;
  }
  // Sweeps: one camera on the whole data, so the framing never moves.
  glm::dvec3 lo, hi;
  session.field().grid.worldBounds(lo, hi);
  const render::StandardView view =
      r.render.view ? *r.render.view
                    : (r.kind == MovieRequest::Kind::Sweep ? render::parseView(r.axis) : render::StandardView::Superior);
  const render::Camera camera = render::Camera::standard(view, lo, hi, aspect, neuro, ortho);
  std::vector<int> indices;
  if (r.kind == MovieRequest::Kind::Sweep) indices = sweepIndices(session.fa(), session.field(), r.axis, r.frames);
  Mesh mesh;
  for (int i = 0; i < r.frames; ++i) {
    const SurfaceSpec spec = r.kind == MovieRequest::Kind::Sweep ? sliceSpec(r.axis, indices[std::size_t(i)])
                                                                 : faSpec(faAt(r, i));
    mesh = session.build(spec);
    session.setMesh(mesh);
    done(i, session.frame(camera, i == 0));
  }
}

} // namespace dtf::session
