// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewer/viewer.h"

#include "io/formats/atomic_file.h"
#include "io/formats/movie_writer.h"
#include "io/model/error.h"
#include "render/fray.h"
#include "render/gl_context.h"
#include "render/text.h"
#include "surfaces/analyses/tract_proximity.h"
#include "surfaces/slices.h"
#include "ui/session/fibre_input.h"
#include "ui/session/movie_job.h"
#include "ui/session/orientation_labels.h"
#include "ui/session/roi_outline.h"
#include "ui/session/tract_colouring.h"
#include "ui/session/tract_overlay.h"
#include "ui/session/tract_profiles.h"
#include "ui/session/viewer_worker.h"

#include <algorithm>
#include <cmath>
#include <epoxy/gl.h>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_inverse.hpp>
#include <limits>
#include <span>
#include <tuple>

namespace dtf::app {

namespace {

constexpr int kStillIterations = 12;    // advection iterations per frame once the camera is still
constexpr double kMotionSeconds = 0.15; // a camera change keeps frames interactive this long
constexpr double kTargetFrameMs = 66;   // interactive frame time the resolution adapts to (15 fps)

const char* const kOrthoAxis[3] = {"axial", "coronal", "sagittal"};

// The entry of a small cache that `match` finds (found = true), else a slot for a new one: appended while
// the cache holds fewer than `cap`, then the oldest replaced in turn (`next` counts the replacements).
template <typename T, typename Match>
T& cacheSlot(std::vector<T>& cache, std::size_t& next, std::size_t cap, Match match, bool& found) {
  auto hit = std::find_if(cache.begin(), cache.end(), match);
  found = hit != cache.end();
  if (found) return *hit;
  if (cache.size() < cap) return cache.emplace_back();
  return cache[next++ % cap];
}
constexpr render::StandardView kOrthoView[3] = {render::StandardView::Axial, render::StandardView::Coronal,
                                                render::StandardView::Sagittal};

// A closed polygon of scene pixels drawn 2 pixels wide into `img`, clipped to `rect` (x, y, w, h).
// A closed polygon, or with `segments` the segments between points 0 and 1, 2 and 3, ...
void drawOutline(Image& img, const std::vector<glm::dvec2>& poly, const std::array<int, 4>& rect,
                 glm::u8vec3 colour, bool segments = false) {
  auto plot = [&](int x, int y) {
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int px = x + dx, py = y + dy;
        if (px < rect[0] || py < rect[1] || px >= rect[0] + rect[2] || py >= rect[1] + rect[3]) continue;
        std::uint8_t* d = img.pixel(px, py);
        d[0] = colour.x, d[1] = colour.y, d[2] = colour.z, d[3] = 255;
      }
  };
  for (std::size_t k = 0; k < poly.size(); k += segments ? 2 : 1) {
    if (segments && k + 1 >= poly.size()) break;
    // The 2-pixel pen's top-left pixel half a pixel up and left of the line.
    const glm::dvec2 a = poly[k] - 0.5, b = poly[(k + 1) % poly.size()] - 0.5;
    const int steps =
        std::max(1, static_cast<int>(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))));
    for (int t = 0; t <= steps; ++t) {
      const glm::dvec2 p = a + (b - a) * (double(t) / steps);
      plot(static_cast<int>(std::floor(p.x + 0.5)), static_cast<int>(std::floor(p.y + 0.5)));
    }
  }
}

} // namespace

struct ViewerScene::Recording {
  std::optional<io::MovieWriter> writer;
  std::string path;
  render::Camera start;
  render::FabricParams params;
  int frames = 0, next = 0;
  glm::ivec2 size{0};
  session::RecordMovie request; // what is recorded (turntable, slice sweep, FA sweep)
  std::vector<int> slices;      // a slice sweep's indices
  Mesh mesh;                    // a sweep's surface of the current frame
};

ViewerScene::ViewerScene(const std::string& surface) : session_(surface) {
  for (auto& r : renderers_)
    r = std::make_unique<render::FabricRenderer>();
  for (auto& r : lowRes_)
    r = std::make_unique<render::FabricRenderer>();
}

ViewerScene::~ViewerScene() = default;

bool ViewerScene::converged() const {
  const bool hasMesh = session_.mesh() != nullptr;
  for (int p = 0; p < paneCount(); ++p) {
    if (dirty_[p] && hasMesh) return false;
    if (paneShowsTracts(p) && hasMesh &&
        (!tractLayer_[p] || !tractLayer_[p]->complete() || tractKeys_[p] != tractKey()))
      return false;
  }
  if (state().ortho && hasMesh)
    for (bool d : orthoDirty_)
      if (d) return false;
  return true;
}

bool ViewerScene::paneShowsTracts(int p) const {
  if (!state().tractsVisible || !tractRenderer_ || tractRenderer_->segmentCount(0) == 0) return false;
  return !(state().split && state().secondPane == session::SecondPane::Tracts && p == 0);
}

std::array<int, 4> ViewerScene::paneRect(int p) const {
  if (state().ortho) {
    const int w2 = std::max(width_ / 2, 1), h2 = std::max(height_ / 2, 1);
    return {w2, h2, std::max(width_ - w2, 1), std::max(height_ - h2, 1)};
  }
  if (!state().split) return {0, 0, width_, height_};
  const int half = std::max(width_ / 2, 1);
  return p == 0 ? std::array<int, 4>{0, 0, half, height_}
                : std::array<int, 4>{half, 0, std::max(width_ - half, 1), height_};
}

int ViewerScene::paneAt(double x) const {
  return paneCount() == 2 && x >= paneRect(1)[0] ? 1 : 0;
}

std::array<int, 4> ViewerScene::orthoRect(int s) const {
  const int w2 = std::max(width_ / 2, 1), h2 = std::max(height_ / 2, 1);
  const int x = s == 1 ? w2 : 0, y = s == 2 ? h2 : 0;
  return {x, y, std::max(s == 1 ? width_ - w2 : w2, 1), std::max(s == 2 ? height_ - h2 : h2, 1)};
}

int ViewerScene::orthoPaneAt(double x, double y) const {
  if (!state().ortho) return -1;
  for (int s = 0; s < 3; ++s) {
    const auto r = orthoRect(s);
    if (x >= r[0] && x < r[0] + r[2] && y >= r[1] && y < r[1] + r[3]) return s;
  }
  return -1;
}

namespace {
// Millimetres per pixel of an orthographic camera over a pane `height` pixels high.
double mmPerPixel(const render::Camera& c, int height) {
  return 2.0 * c.orthoHalfHeight / std::max(height, 1);
}
} // namespace

glm::dvec2 ViewerScene::orthoPixel(int s, const glm::dvec3& world) const {
  const render::Camera& c = orthoCameras_[s];
  const auto r = orthoRect(s);
  const glm::dvec3 right = c.right(), up = glm::normalize(glm::cross(right, c.forward()));
  const double mm = mmPerPixel(c, r[3]);
  const glm::dvec3 d = world - c.target;
  return {r[0] + 0.5 * r[2] + glm::dot(d, right) / mm, r[1] + 0.5 * r[3] - glm::dot(d, up) / mm};
}

glm::dvec3 ViewerScene::orthoWorld(int s, double x, double y) const {
  const render::Camera& c = orthoCameras_[s];
  const auto r = orthoRect(s);
  const glm::dvec3 right = c.right(), up = glm::normalize(glm::cross(right, c.forward()));
  const double mm = mmPerPixel(c, r[3]);
  const glm::dvec3 at = c.target + right * ((x - r[0] - 0.5 * r[2]) * mm) - up * ((y - r[1] - 0.5 * r[3]) * mm);
  // The point of this pane's slice plane: the crosshair's depth along the view is kept.
  const glm::dvec3 fwd = c.forward(), cross = state().crosshair;
  return at - glm::dot(at - cross, fwd) * fwd;
}

bool ViewerScene::clickAt(double x, double y) {
  const int s = orthoPaneAt(x, y);
  if (s < 0 || !session_.dataset()) return false;
  apply(session::SetCrosshair{orthoWorld(s, x, y)});
  return true;
}

bool ViewerScene::regionOutlinePixels(int s, std::size_t i, std::vector<glm::dvec2>& out, bool* segments) const {
  out.clear();
  const session::ViewerState& st = state();
  if (!st.ortho || i >= st.roiSet.regions.size() || !orthoPlanes_[s]) return false;
  if (i < st.roiVisible.size() && !st.roiVisible[i]) return false;
  const glm::dvec4 plane(*orthoPlanes_[s]);
  const glm::dvec3 n(plane);
  const surfaces::Region& r = st.roiSet.regions[i];
  const bool mask = r.shape == surfaces::RegionShape::Mask;
  if (segments) *segments = mask;
  const std::vector<glm::dvec3>* world = &outlineWorld_;
  if (mask) {
    const glm::vec4 key = *orthoPlanes_[s];
    bool found = false;
    MaskOutline& hit = cacheSlot(maskOutlines_, nextMaskOutline_, kMaskOutlineCache,
                                 [&](const MaskOutline& m) { return m.mask == r.mask && m.plane == key; }, found);
    if (!found) {
      hit.mask = r.mask;
      hit.plane = key;
      hit.cuts = session::maskOutline(r, -plane.w * n, n, hit.segments, outlineSamples_);
    }
    if (!hit.cuts) return false;
    world = &hit.segments;
  } else if (!session::regionOutline(r, -plane.w * n, n, outlineWorld_)) {
    return false;
  }
  for (const glm::dvec3& p : *world)
    out.push_back(orthoPixel(s, p));
  return true;
}

session::RoiSet ViewerScene::regionDragged(std::size_t i, const surfaces::Region& start, int s,
                                           const glm::dvec3& from, double x, double y) const {
  const glm::dvec3 d = orthoWorld(s, x, y) - from;
  session::RoiSet set{i, start};
  set.region.centre += d;
  set.region.lo += d;
  set.region.hi += d;
  return set;
}

std::optional<session::RoiSet> ViewerScene::regionScaled(double x, double y, double notches) const {
  const int i = regionAt(x, y);
  if (i < 0) return std::nullopt;
  session::RoiSet set{std::size_t(i), state().roiSet.regions[std::size_t(i)]};
  const double f = std::pow(1.1, notches);
  surfaces::Region& r = set.region;
  if (r.shape == surfaces::RegionShape::Box) {
    const glm::dvec3 c = 0.5 * (r.lo + r.hi), h = 0.5 * (r.hi - r.lo) * f;
    r.lo = c - h, r.hi = c + h;
  } else {
    r.radius = std::clamp(r.radius * f, 0.5, 200.0);
  }
  return set;
}

int ViewerScene::regionAt(double x, double y) const {
  const int s = orthoPaneAt(x, y);
  const session::ViewerState& st = state();
  if (s < 0 || !orthoPlanes_[s]) return -1;
  // The slice plane's point under the pixel (the slice itself, not the crosshair's depth).
  const glm::dvec4 plane(*orthoPlanes_[s]);
  const glm::dvec3 n(plane), at = orthoWorld(s, x, y);
  const glm::dvec3 p = at - (glm::dot(at, n) + plane.w) * n;
  for (std::size_t i = st.roiSet.regions.size(); i-- > 0;) {
    const surfaces::Region& r = st.roiSet.regions[i];
    if (r.shape == surfaces::RegionShape::Mask || (i < st.roiVisible.size() && !st.roiVisible[i])) continue;
    if (r.contains(glm::vec3(p))) return static_cast<int>(i);
  }
  return -1;
}

double ViewerScene::paneAspect(int p) const {
  auto r = paneRect(p);
  return static_cast<double>(r[2]) / std::max(r[3], 1);
}

render::Camera& ViewerScene::cameraFor(int pane) {
  if (state().linked) return cameras_[0];
  return cameras_[pane < 0 ? activePane_ : std::clamp(pane, 0, 1)];
}

void ViewerScene::cameraChanged() {
  lastMotion_ = std::chrono::steady_clock::now();
  dataChanged();
}

void ViewerScene::dataChanged() {
  dirty_.fill(true);
  iterationsSinceRestart_.fill(0);
  covered_.fill(0);
  // The slice panes of the ortho layout weave the same data: they start again too (a new background, the
  // fabric along the tracts, new parameters).
  orthoDirty_.fill(true);
  orthoIterations_.fill(0);
  orthoCovered_.fill(0);
  session_.state().converged = false;
}

void ViewerScene::setView(render::StandardView v) {
  session::ViewerState& state = session_.state();
  state.view = v;
  const auto data = session_.dataset();
  if (!data) return;
  for (int p = 0; p < 2; ++p) {
    if (!state.linked && p != activePane_) continue;
    cameras_[p] = render::Camera::standard(v, data->lo, data->hi, paneAspect(p), state.neurological);
  }
  if (state.linked) cameras_[1] = cameras_[0];
  cameraChanged();
}

void ViewerScene::uploadField(render::FabricRenderer& r, int slot) {
  const auto data = session_.dataset();
  const bool principal = data && !data->fibres && state().fabric.colour == render::ColourMode::Fibres;
  if (data && (fieldUploaded_[slot] != session_.fieldSerial() || principalUploaded_[slot] != principal)) {
    if (fieldUploaded_[slot] != session_.fieldSerial()) r.setField(data->loaded.field);
    if (data->fibres) {
      r.setFibres(data->fibres->set, data->fa.data.empty() ? nullptr : &data->fa);
    } else if (principal) {
      // A tensor in the fibres colour mode: its principal directions as one population, as `render` does.
      if (!principal_ || principalSerial_ != session_.fieldSerial()) {
        principal_ = session::principalFibres(data->loaded.field);
        principalSerial_ = session_.fieldSerial();
      }
      r.setFibres(*principal_);
    } else {
      r.clearFibres();
    }
    fieldUploaded_[slot] = session_.fieldSerial();
    principalUploaded_[slot] = principal;
  }
  if (uncertainty_ && (coneBuilt_ != coneSerial_ || coneField_ != session_.fieldSerial())) {
    cone_ = session::conesFor(*uncertainty_, data && data->fibres ? &data->fibres->set : nullptr);
    coneBuilt_ = coneSerial_;
    coneField_ = session_.fieldSerial();
    coneUploaded_.fill(0);
  }
  if (backgroundUploaded_[slot] != backgroundVersion_) {
    if (background_)
      r.setBackground(&background_->volume, background_->lo, background_->hi);
    else
      r.setBackground(nullptr);
    backgroundUploaded_[slot] = backgroundVersion_;
  }
  if (alongUploaded_[slot] != alongVersion_) {
    r.setAlong(alongWeight_ ? alongWeight_.get() : nullptr);
    alongUploaded_[slot] = alongVersion_;
  }
  if (coneUploaded_[slot] != coneSerial_) {
    r.setUncertainty(uncertainty_ ? &cone_ : nullptr);
    coneUploaded_[slot] = coneSerial_;
  }
}

render::FabricRenderer& ViewerScene::upToDate(std::unique_ptr<render::FabricRenderer>& r, int slot) {
  uploadField(*r, slot);
  if (session_.mesh() && meshUploaded_[slot] != session_.meshSerial()) {
    r->setMesh(*session_.mesh());
    meshUploaded_[slot] = session_.meshSerial();
  }
  return *r;
}

void ViewerScene::update() {
  session_.update();
  // Uploads happen when a renderer next draws: a sweep without split view feeds one or two renderers, not
  // four.
  if (session_.fieldSerial() != seenField_) {
    seenField_ = session_.fieldSerial();
    hasField_ = true;
    dataChanged();
  }
  if (session_.loadSerial() != seenLoad_) {
    seenLoad_ = session_.loadSerial();
    if (const auto data = session_.dataset()) session_.state().crosshair = 0.5 * (data->lo + data->hi);
    crosshairOnMesh_ = true;
    setView(session_.homeView());
  }
  updateAlong();
  updateProfile();
  resolveBackground();
  if (session_.meshSerial() != seenMesh_) {
    seenMesh_ = session_.meshSerial();
    // The first surface of a load that is flat along a world axis (an axis-aligned slice) puts the
    // crosshair on its plane, so `--surface slice=axial:22` opens the ortho layout on axial 22 too.
    const auto mesh = session_.mesh();
    if (crosshairOnMesh_ && mesh && !mesh->empty()) {
      crosshairOnMesh_ = false;
      glm::vec3 lo, hi;
      mesh->bounds(lo, hi);
      const auto data = session_.dataset();
      for (int a = 0; a < 3 && data; ++a)
        if (double(hi[a] - lo[a]) < 1e-3 * (data->hi[a] - data->lo[a]))
          session_.state().crosshair[a] = 0.5 * double(lo[a] + hi[a]);
    }
    cameraChanged(); // a new mesh while sweeping counts as motion: interactive frames, not still refinement
  }
  if (state().ortho) {
    try {
      updateOrtho();
    } catch (...) {
      session_.setError("while cutting the ortho slices: " + currentExceptionMessage());
    }
  }
  if (session_.displaySerial() != seenDisplay_ && session_.tractDisplay()) {
    seenDisplay_ = session_.displaySerial();
    try {
      if (!tractRenderer_) {
        tractRenderer_ = std::make_unique<render::TractRenderer>();
        setNodeColours(*tractRenderer_);
      }
      if (session_.tractDisplay() != uploaded_) {
        tractRenderer_->upload(*session_.tractDisplay());
        uploaded_ = session_.tractDisplay();
      }
    } catch (...) {
      session_.setError("while uploading the tracts: " + currentExceptionMessage());
    }
  }
  if (state().ortho && session_.tractDisplayAll() != orthoUploaded_) {
    // The slice panes draw every tract in a slab around their planes (uploaded only in the ortho layout).
    try {
      if (!orthoTracts_) {
        orthoTracts_ = std::make_unique<render::TractRenderer>();
        setNodeColours(*orthoTracts_);
      }
      if (session_.tractDisplayAll())
        orthoTracts_->upload(*session_.tractDisplayAll());
      else
        orthoTracts_->upload(render::DisplayTracts{});
      orthoUploaded_ = session_.tractDisplayAll();
      orthoDirty_.fill(true);
    } catch (...) {
      orthoUploaded_ = session_.tractDisplayAll(); // do not repeat a failing upload every frame
      session_.setError("while uploading the tracts for the slice panes: " + currentExceptionMessage());
    }
  }
  updateNodeColours();
}

void ViewerScene::updateOrtho() {
  session::ViewerState& st = session_.state();
  const auto data = session_.dataset();
  if (!data) return;
  const Grid& grid = data->loaded.field.grid;
  const int neuro = st.neurological ? 1 : 0;
  const bool newField = orthoField_ != session_.fieldSerial();
  if (newField || orthoCameraKey_ != std::array<int, 3>{width_, height_, neuro}) {
    orthoCameraKey_ = {width_, height_, neuro};
    for (int s = 0; s < 3; ++s) {
      const auto r = orthoRect(s);
      orthoCameras_[s] = render::Camera::standard(kOrthoView[s], data->lo, data->hi,
                                                  double(r[2]) / std::max(r[3], 1), st.neurological);
      orthoDirty_[s] = true;
    }
    // One scale for the three slices (the largest that fits each pane), so a millimetre is as long in
    // every pane and the crosshair's lines meet the same anatomy at the same size.
    double halfHeight = 0;
    for (const render::Camera& c : orthoCameras_)
      halfHeight = std::max(halfHeight, c.orthoHalfHeight);
    for (render::Camera& c : orthoCameras_)
      c.orthoHalfHeight = halfHeight;
  }
  if (newField) {
    orthoField_ = session_.fieldSerial();
    orthoBuilt_ = {-1, -1, -1};
  }
  const glm::dvec3 ijk = grid.toVoxel(st.crosshair);
  for (int s = 0; s < 3; ++s) {
    const auto axis = static_cast<surfaces::SliceAxis>(s);
    const int va = surfaces::voxelAxisFor(grid, axis);
    const int index = std::clamp(static_cast<int>(std::lround(ijk[va])), 0, grid.dims[va] - 1);
    st.orthoSlice[s] = index;
    if (index == orthoBuilt_[s]) continue;
    orthoBuilt_[s] = index;
    try {
      orthoMeshes_[s] = session::extractViewerSurface(
          *data, session::parseSurfaceSpec(std::string("slice=") + kOrthoAxis[s] + ":" + std::to_string(index)));
    } catch (const InputError&) {
      orthoMeshes_[s] = Mesh{}; // no data in this slice: the pane stays empty
    }
    orthoPlanes_[s] = orthoMeshes_[s].empty() ? std::nullopt : session::pickTracts(orthoMeshes_[s], 0.0).plane;
    orthoMeshNew_[s] = true;
    orthoDirty_[s] = true;
    orthoIterations_[s] = 0;
    orthoCovered_[s] = 0;
  }
}

void ViewerScene::renderOrtho(const render::FabricParams& base) {
  // The tracts of the slice panes: every tract drawn within a slab around each pane's plane, the clip slab's
  // half-width when set, else the near-surface distance (0: every tract), as on a planar surface.
  const session::ViewerState& st = state();
  const bool tracts = st.tractsVisible && orthoTracts_ && orthoTracts_->segmentCount(0) > 0;
  const double slabMm = st.tractsClipMm > 0 ? st.tractsClipMm : st.tractsNearMm;
  std::uint64_t key = tracts ? 1 : 0;
  for (double v : {st.tractWidthPx, slabMm})
    key = key * 1000003u + static_cast<std::uint64_t>(std::llround(v * 1000.0));
  key = (key * 1013 + nodeColourSerial_) * 131 + static_cast<std::uint64_t>(highlightedNode() + 1);
  if (key != orthoTractKey_) {
    orthoTractKey_ = key;
    orthoDirty_.fill(true);
  }
  for (int s = 0; s < 3; ++s) {
    if (!orthoDirty_[s]) continue;
    if (orthoMeshes_[s].empty()) {
      orthoDirty_[s] = false;
      continue;
    }
    if (!orthoRenderers_[s]) orthoRenderers_[s] = std::make_unique<render::FabricRenderer>();
    render::FabricRenderer& r = *orthoRenderers_[s];
    uploadField(r, 4 + s);
    if (orthoMeshNew_[s]) {
      r.setMesh(orthoMeshes_[s]);
      orthoMeshNew_[s] = false;
    }
    const auto rect = orthoRect(s);
    r.resize(rect[2], rect[3]);
    render::FabricParams params = base;
    params.iterations = std::max(params.iterations, kStillIterations);
    r.renderFrame(orthoCameras_[s], params);
    if (tracts && orthoPlanes_[s]) {
      render::TractStyle style;
      style.widthPx = static_cast<float>(st.tractWidthPx);
      style.highlightNode = highlightedNode();
      style.plane = *orthoPlanes_[s];
      style.slabMm = static_cast<float>(slabMm);
      // The slab's far half lies behind the slice: drawn in front of it all the same.
      style.depthBiasMm = static_cast<float>(slabMm > 0 ? slabMm + 0.05 : 0.05);
      glBindFramebuffer(GL_FRAMEBUFFER, r.output().id());
      orthoTracts_->draw(r.frameView(), style);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    orthoIterations_[s] += params.iterations;
    if (orthoCovered_[s] == 0) orthoCovered_[s] = std::max(r.coveredPixels(), 1u);
    // The rule of renderStill (no count before FabricParams::stillMinIterations since the restart).
    if (r.changedPixels() <= params.stillChangedFraction * orthoCovered_[s] ||
        orthoIterations_[s] >= std::max(params.stillMaxIterations, kStillIterations))
      orthoDirty_[s] = false;
  }
}

void ViewerScene::updateAlong() {
  session::ViewerState& st = session_.state();
  TractSubset lines = st.fabricAlong ? selectedTracts() : TractSubset{};
  if (lines.lines && lines.lines->points.empty()) lines = {};
  if (lines != alongLines_ || (lines.lines && st.fabricAlongMm != alongMm_)) {
    alongLines_ = lines;
    alongMm_ = st.fabricAlongMm;
    ++alongSerial_;
    if (lines.lines) {
      if (!alongWorker_)
        alongWorker_ = std::make_unique<session::CoalescingWorker<AlongJob, AlongResult>>(
            [](AlongJob& job, session::WorkContext& context) -> std::optional<AlongResult> {
              AlongResult r;
              r.serial = job.serial;
              try {
                context.setStage("the fabric along the tracts");
                surfaces::TractProximityOptions o;
                o.mm = job.mm;
                surfaces::TractProximity near = surfaces::tractProximity(*job.lines, o, job.which.get());
                // No streamline selected: the fabric nowhere (a weight of 0; an empty volume would mean
                // everywhere).
                if (near.points == 0)
                  near.weight = ScalarVolume(Grid::fromAffine({1, 1, 1}, glm::dmat4(1.0)), 1);
                r.weight = std::make_shared<const ScalarVolume>(std::move(near.weight));
              } catch (...) {
                r.error = currentExceptionMessage();
              }
              return r;
            },
            std::vector<session::WorkLane>{{true, true}});
      alongWorker_->request(AlongJob{lines.lines, lines.which, st.fabricAlongMm, alongSerial_});
    } else if (alongWeight_) {
      alongWeight_.reset();
      ++alongVersion_;
      ++backgroundSerial_; // FA beneath only while the fabric follows the tracts
      dataChanged();
    }
  }
  if (!alongWorker_) return;
  AlongResult r;
  while (alongWorker_->poll(r)) {
    if (r.serial != alongSerial_) continue; // out of date
    if (!r.error.empty()) session_.setError("while building the fabric along the tracts: " + r.error);
    alongWeight_ = std::move(r.weight);
    ++alongVersion_;
    ++backgroundSerial_;
    dataChanged();
  }
  st.fabricAlongPending = alongWorker_->busy();
}

void ViewerScene::updateProfile() {
  session::ViewerState::Profile& pr = session_.state().profile;
  const auto data = session_.dataset();
  // Profiled while the panel is on or the tracts are coloured by the profile's value.
  const bool wanted = pr.on || session_.state().tractColourBy == session::kProfileColouring;
  ProfileSource src = wanted ? selectedTracts() : ProfileSource{};
  if (src.lines && src.lines->points.empty()) src = {};
  if (data && data != profiledData_) pr.scalars = session::viewerProfileScalars(*data);
  if (src.lines != profiled_.lines || src.which != profiled_.which || data != profiledData_ ||
      pr.scalar != profiledScalar_) {
    profiled_ = src;
    profiledData_ = data;
    profiledScalar_ = pr.scalar;
    ++profileSerial_;
    pr.hovered = pr.pinned = -1;
    if (src.lines && data) {
      if (!profileWorker_)
        profileWorker_ = std::make_unique<
            session::CoalescingWorker<session::ViewerProfileJob, session::ViewerProfileResult>>(
            [](session::ViewerProfileJob& job,
               session::WorkContext& context) -> std::optional<session::ViewerProfileResult> {
              context.setStage("profiling the tracts");
              return session::profileForViewer(job);
            },
            std::vector<session::WorkLane>{{true, true}});
      profileWorker_->request(
          session::ViewerProfileJob{src.lines, src.which, data, pr.scalar, profileSerial_});
    } else {
      pr.mean.clear();
      pr.ciLow.clear();
      pr.ciHigh.clear();
      pr.core.clear();
      pr.streamlines = 0;
      pr.error = wanted && data ? "no tracts to profile" : "";
    }
  }
  if (!profileWorker_) return;
  session::ViewerProfileResult r;
  while (profileWorker_->poll(r)) {
    if (r.serial != profileSerial_) continue; // out of date
    ++profileResults_;
    pr.error = r.error;
    pr.axis = r.axis;
    pr.streamlines = r.profile.streamlines;
    // The panel's font has no arrow: "inferior -> superior".
    for (std::size_t at; (at = pr.axis.find("\u2192")) != std::string::npos;)
      pr.axis.replace(at, 3, "->");
    pr.core = std::move(r.profile.core);
    if (r.profile.scalars.empty()) {
      pr.mean.clear();
      pr.ciLow.clear();
      pr.ciHigh.clear();
    } else {
      pr.mean = std::move(r.profile.scalars[0].mean);
      pr.ciLow = std::move(r.profile.scalars[0].ciLow);
      pr.ciHigh = std::move(r.profile.scalars[0].ciHigh);
    }
  }
  pr.pending = profileWorker_->busy();
}

int ViewerScene::highlightedNode() const {
  const session::ViewerState::Profile& pr = state().profile;
  if (!pr.on) return -1;
  return pr.hovered >= 0 ? pr.hovered : pr.pinned;
}

void ViewerScene::updateNodeColours() {
  const session::ViewerState& st = state();
  const bool coloured = st.tractColourBy == session::kProfileColouring;
  const auto& range = session_.tractColour().range;
  const std::uint64_t want = coloured ? profileResults_ : ~0ull;
  if (want == nodeColoursFor_ && range == nodeColourRange_) return;
  nodeColoursFor_ = want;
  nodeColourRange_ = range;
  ++nodeColourSerial_;
  nodeColourCount_ = 0;
  const std::vector<double>& mean = st.profile.mean;
  if (coloured && !mean.empty() && mean.size() <= nodeColours_.size()) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : mean)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (range) std::tie(lo, hi) = *range;
    if (lo <= hi) {
      for (std::size_t k = 0; k < mean.size(); ++k) {
        const float t = hi > lo ? static_cast<float>((mean[k] - lo) / (hi - lo)) : 0.5f;
        nodeColours_[k] =
            std::isfinite(mean[k]) ? glm::vec4(render::tractValueColour(t), 1.0f) : glm::vec4(0.0f);
      }
      nodeColourCount_ = mean.size();
      session_.state().tractColourLo = lo;
      session_.state().tractColourHi = hi;
    }
  }
  if (tractRenderer_) setNodeColours(*tractRenderer_);
  if (orthoTracts_) setNodeColours(*orthoTracts_);
}

void ViewerScene::setNodeColours(render::TractRenderer& r) const {
  r.setNodeColours(std::span<const glm::vec4>(nodeColours_.data(), nodeColourCount_));
}

void ViewerScene::profileCrosshair() {
  session::ViewerState& state = session_.state();
  const session::ViewerState::Profile& pr = state.profile;
  const int node = pr.hovered >= 0 ? pr.hovered : pr.pinned;
  const auto data = session_.dataset();
  if (node < 0 || node >= static_cast<int>(pr.core.size()) || !data) return;
  state.crosshair = glm::clamp(pr.core[static_cast<std::size_t>(node)], data->lo, data->hi);
  if (state.ortho) updateOrtho();
}

void ViewerScene::resolveBackground() {
  const auto data = session_.dataset();
  const bool anatomy = state().fabric.look == render::Look::Anatomy;
  const std::uint64_t field = session_.fieldSerial();
  if (backgroundResolved_ == backgroundSerial_ && backgroundField_ == field && backgroundAnatomy_ == anatomy)
    return;
  backgroundResolved_ = backgroundSerial_;
  backgroundField_ = field;
  backgroundAnatomy_ = anatomy;
  const bool had = background_.has_value();
  background_.reset();
  std::string& shown = session_.state().background;
  shown.clear();
  const std::string& what = backgroundAsked_.what;
  if (data && what.empty() && anatomy && !data->loaded.meanB0.data.empty()) {
    session::Background b;
    b.volume = data->loaded.meanB0;
    if (session::windowByPercentiles(b)) {
      background_ = std::move(b);
      shown = "mean b=0";
    }
  } else if (data && !what.empty() && what != "none") {
    try {
      session::Background b = session::loadBackground(what, backgroundAsked_.window, data->loaded.field, data->fa);
      if (b.volume.data.empty()) throw UsageError("--background " + what + " needs FA: these data have none");
      background_ = std::move(b);
      shown = what;
    } catch (...) {
      session_.setError("while loading the background " + what + ": " + currentExceptionMessage());
    }
  }
  // The fabric along the tracts shows the anatomy away from them: FA when nothing else lies beneath.
  if (data && !background_ && alongWeight_ && what != "none" && !data->fa.data.empty()) {
    session::Background b;
    b.volume = data->fa;
    background_ = std::move(b);
    shown = "fa (the fabric along the tracts)";
  }
  if (had || background_) {
    ++backgroundVersion_;
    dataChanged();
  }
}

namespace {

// A pane of the scene as a canvas: offset to its rectangle and clipped to it.
// A pane of the scene canvas, magnified `scale` times: the furniture is laid out on a canvas 1/scale the
// pane's size and each of its pixels covers scale x scale scene pixels (the UI scale).
class PaneCanvas final : public render::Canvas {
public:
  PaneCanvas(render::Canvas& scene, const std::array<int, 4>& rect, double scale)
      : scene_(scene), r_(rect), s_(scale) {}
  int width() const override { return static_cast<int>(r_[2] / s_); }
  int height() const override { return static_cast<int>(r_[3] / s_); }
  void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) override {
    const auto at = [&](int v) { return static_cast<int>(std::floor(v * s_)); };
    const int x0 = std::max(at(x), 0), y0 = std::max(at(y), 0), x1 = std::min(at(x + w), r_[2]),
              y1 = std::min(at(y + h), r_[3]);
    if (x0 < x1 && y0 < y1) scene_.fill(r_[0] + x0, r_[1] + y0, x1 - x0, y1 - y0, r, g, b);
  }
  void blend(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
             std::uint8_t alpha) override {
    const int x0 = std::max(x, 0), y0 = std::max(y, 0), x1 = std::min(x + w, r_[2]), y1 = std::min(y + h, r_[3]);
    if (x0 < x1 && y0 < y1) scene_.blend(r_[0] + x0, r_[1] + y0, x1 - x0, y1 - y0, r, g, b, alpha);
  }

private:
  render::Canvas& scene_;
  std::array<int, 4> r_;
  double s_;
};

} // namespace

void ViewerScene::drawFurniture(render::Canvas& scene, double scale) const {
  const session::ViewerState& st = state();
  if (!session_.mesh() || !st.hasData) return;
  if (colourBar_.name != st.tractColourBy) colourBar_.name = st.tractColourBy;
  colourBar_.lo = st.tractColourLo;
  colourBar_.hi = st.tractColourHi;
  constexpr int kFrayScale = 1;
  auto pane = [&](const std::array<int, 4>& rect, const render::Camera& cam, bool tracts, bool fray) {
    PaneCanvas c(scene, rect, scale);
    render::FigureFurniture what;
    what.letters = false; // the window labels every pane's edges itself
    what.legend = st.legend;
    what.scaleBar = st.scaleBar && cam.orthographic;
    if (fray) what.bottomLeftReserved = render::frayLegendHeight(kFrayScale);
    render::drawFurniture(c, cam, mmPerPixel(cam, rect[3]) * scale, what);
    if (tracts && st.colourBar && !st.tractColourBy.empty()) render::drawColourBar(c, colourBar_);
    if (fray) render::drawFrayLegend(c, static_cast<float>(st.fabric.fray), kFrayScale);
  };
  for (int p = 0; p < paneCount(); ++p)
    pane(paneRect(p), camera(p), paneShowsTracts(p), uncertainty_ && p == 0);
  if (st.ortho)
    for (int s = 0; s < 3; ++s)
      if (!orthoMeshes_[s].empty()) pane(orthoRect(s), orthoCameras_[s], false, false);
}

void ViewerScene::startRecording(const session::RecordMovie& a) {
  const auto data = session_.dataset();
  if (!data || !session_.mesh()) throw UsageError("load data before recording a movie");
  if (a.frames < 1 || a.frames > 10000) throw UsageError("a movie has 1 to 10000 frames");
  io::refuseMovieOverInputs(a.path, {data->path});
  const auto rect = paneRect(0);
  auto rec = std::make_unique<Recording>();
  rec->size = {rect[2], rect[3]};
  if (io::movieFormatOf(a.path) == io::MovieFormat::Mp4) rec->size = {rect[2] / 2 * 2, rect[3] / 2 * 2};
  rec->writer.emplace(a.path, rec->size.x, rec->size.y, a.fps, true); // mayWrite said yes
  rec->path = a.path;
  rec->request = a;
  if (a.kind == session::RecordMovie::Kind::Sweep)
    rec->slices = session::sweepIndices(data->fa, data->loaded.field, a.axis, a.frames);
  if (a.kind == session::RecordMovie::Kind::FaSweep && data->fa.data.empty())
    throw UsageError("an FA sweep needs FA: pair a tensor with the fibre set");
  rec->start = camera(0);
  rec->params = session_.fabricOnScreen();
  rec->frames = a.frames;
  recording_ = std::move(rec);
  session::ViewerState& st = session_.state();
  st.recording = true;
  st.recordedFrames = 0;
  st.recordFrames = a.frames;
  st.recordStatus = "recording " + a.path;
}

void ViewerScene::recordFrame() {
  Recording& rec = *recording_;
  session::ViewerState& st = session_.state();
  try {
    if (!recorder_) recorder_ = std::make_unique<render::FabricRenderer>();
    render::FabricRenderer& r = *recorder_;
    uploadField(r, 7);
    if (rec.next == 0) r.resize(rec.size.x, rec.size.y);
    using K = session::RecordMovie::Kind;
    render::Camera cam = rec.start;
    if (rec.request.kind == K::Turntable) {
      if (rec.next == 0) r.setMesh(*session_.mesh());
      // About the pane's vertical: the screen's up direction through the camera's target.
      const glm::dvec3 up = glm::normalize(glm::cross(rec.start.right(), rec.start.forward()));
      cam = session::turnedAbout(rec.start, up, 360.0 * rec.next / rec.frames);
    } else {
      // Sweeps: the pane's camera held, the surface of this frame cut on the UI thread (one per frame).
      const auto data = session_.dataset();
      const session::SurfaceSpec spec =
          rec.request.kind == K::Sweep
              ? session::sliceSweepSpec(rec.request.axis, rec.slices[static_cast<std::size_t>(rec.next)])
              : session::faSweepSpec(rec.request.faLo, rec.request.faHi, rec.next, rec.frames);
      rec.mesh = session::extractViewerSurface(*data, spec);
      r.setMesh(rec.mesh);
    }
    r.renderMovieFrame(cam, rec.params, rec.next == 0);
    rec.writer->add(r.readback());
    st.recordedFrames = ++rec.next;
    if (rec.next == rec.frames) {
      rec.writer->finish();
      st.recordStatus = "wrote " + std::to_string(rec.frames) + " frames to " + rec.path;
      std::fprintf(stderr, "%s\n", st.recordStatus.c_str());
      recording_.reset();
      st.recording = false;
    }
  } catch (...) {
    const std::string path = rec.path;
    recording_.reset(); // removes what was written
    st.recording = false;
    st.recordStatus = "recording failed";
    session_.setError("while recording " + path + ": " + currentExceptionMessage());
  }
}

// The right pane's colour mode in the split "other colour mode": medical and engineering swap; a fibre set
// with a paired tensor shows the tensor's medical colours beside its fibres (DTI beside the fibre set); a
// tensor in the fibres mode shows its medical colours.
render::ColourMode ViewerScene::otherColour(render::ColourMode mode) const {
  using C = render::ColourMode;
  const auto data = session_.dataset();
  if (mode == C::Fibres) return data && data->fibres && !data->pairedTensor ? C::Fibres : C::Medical;
  return mode == C::Medical ? C::Engineering : C::Medical;
}

void ViewerScene::render(int width, int height) {
  session::ViewerState& state = session_.state();
  width = std::max(width, 1);
  height = std::max(height, 1);
  if (width != width_ || height != height_) {
    width_ = width;
    height_ = height;
    dataChanged();
  }
  if (!session_.mesh() || !hasField_) return;
  if (recording_) recordFrame();
  const auto now = std::chrono::steady_clock::now();
  const bool moving =
      interacting_ || std::chrono::duration<double>(now - lastMotion_).count() < kMotionSeconds;
  if (moving && state.frameMs > 0 && interactiveScale_ < 1.0) {
    const double wanted = scale_ * std::clamp(std::sqrt(kTargetFrameMs / state.frameMs), 0.7, 1.3);
    scale_ = std::clamp(std::round(wanted * 8.0) / 8.0, 0.25, interactiveScale_);
  }
  std::array<bool, 2> fabricChanged{false, false};
  try {
    for (int p = 0; p < paneCount(); ++p) {
      const bool shows = paneShowsTracts(p);
      if (tractsShown_[p] && !shows) { // the output holds tracts: render the fabric alone again
        for (int slot : {p, 2 + p})
          if (tractLayers_[slot]) tractLayers_[slot]->reset();
        dirty_[p] = true;
      }
      tractsShown_[p] = shows;
    }
    for (int p = 0; p < paneCount(); ++p) {
      if (!dirty_[p]) continue;
      fabricChanged[p] = true;
      const auto rect = paneRect(p);
      const render::Camera& cam = camera(p);
      const bool low = moving && interactiveScale_ < 1.0;
      const double scale = low ? scale_ : 1.0;
      const glm::ivec2 size(std::max(1, static_cast<int>(rect[2] * scale)),
                            std::max(1, static_cast<int>(rect[3] * scale)));
      render::FabricRenderer& r = low ? upToDate(lowRes_[p], 2 + p) : upToDate(renderers_[p], p);
      r.resize(size.x, size.y);
      outputRenderer_[p] = &r;
      outputSize_[p] = size;
      if (p == 1 && state.secondPane == session::SecondPane::Phong) {
        r.renderPhong(cam);
        outputFbo_[p] = r.output().id();
        dirty_[p] = low;
        continue;
      }
      render::FabricParams params = session_.fabricOnScreen();
      if (p == 1 && state.secondPane == session::SecondPane::OtherColourMode)
        params.colour = otherColour(params.colour);
      if (low) {
        params.autoLodPixels *= scale;
        params.stepPixels *= scale;
        params.guard = std::max(1, static_cast<int>(params.guard * scale));
      }
      if (!moving) params.iterations = std::max(params.iterations, kStillIterations);
      r.renderFrame(cam, params);
      outputFbo_[p] = r.output().id();
      if (moving) {
        iterationsSinceRestart_[p] = 0;
        covered_[p] = 0;
        continue;
      }
      iterationsSinceRestart_[p] += params.iterations;
      // Still: refine until almost no covered pixel changes by more than epsilon (the renderStill rule: the
      // renderer counts no frame before the start image has faded, FabricParams::stillMinIterations).
      if (covered_[p] == 0) covered_[p] = std::max(r.coveredPixels(), 1u);
      if (r.changedPixels() <= params.stillChangedFraction * covered_[p] ||
          iterationsSinceRestart_[p] >= std::max(params.stillMaxIterations, kStillIterations))
        dirty_[p] = false;
    }
    for (int p = 0; p < paneCount(); ++p)
      if (tractsShown_[p] && outputRenderer_[p] && outputFbo_[p]) tractFrame(p, fabricChanged[p], moving);
    if (state.ortho) renderOrtho(state.fabric);
    static const std::string where = "rendering the fabric"; // no allocation per frame
    render::checkGl(where);
  } catch (...) {
    dirty_.fill(false); // do not repeat a failing frame every frame
    orthoDirty_.fill(false);
    try {
      throw;
    } catch (const GlError&) {
      // The field or the passes do not fit this GL (texture limits, GPU memory, shaders): draw nothing more
      // of these data; the window stays up and another file can be loaded.
      glFailed_ = true;
      hasField_ = false;
      outputFbo_.fill(0);
    } catch (...) {
    }
    session_.setError("while rendering: " + currentExceptionMessage());
  }
  state.converged = converged();
}

void ViewerScene::present(unsigned fbo, int x, int y) {
  for (int p = 0; p < paneCount(); ++p) {
    if (!outputFbo_[p] || !session_.mesh()) continue;
    const auto rect = paneRect(p);
    const glm::ivec2 src = outputSize_[p];
    const bool same = src.x == rect[2] && src.y == rect[3];
    const int y0 = y + height_ - rect[1] - rect[3]; // GL rows count up from the scene's bottom
    glBlitNamedFramebuffer(outputFbo_[p], fbo, 0, 0, src.x, src.y, x + rect[0], y0, x + rect[0] + rect[2],
                           y0 + rect[3], GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  }
  if (!state().ortho) return;
  for (int s = 0; s < 3; ++s) {
    if (!orthoRenderers_[s] || orthoMeshes_[s].empty()) continue;
    const auto rect = orthoRect(s);
    const int y0 = y + height_ - rect[1] - rect[3];
    glBlitNamedFramebuffer(orthoRenderers_[s]->output().id(), fbo, 0, 0, rect[2], rect[3], x + rect[0], y0,
                           x + rect[0] + rect[2], y0 + rect[3], GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
}

void ViewerScene::readPane(unsigned fbo, glm::ivec2 size, const std::array<int, 4>& rect, Image& into) const {
  if (!fbo || size.x < 1 || size.y < 1) return;
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(size.x) * size.y * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // Nearest sampling of the output onto the pane (the same size once the pane is still).
  for (int y = 0; y < rect[3]; ++y) {
    const int sy = size.y - 1 - std::min(y * size.y / std::max(rect[3], 1), size.y - 1);
    for (int x = 0; x < rect[2]; ++x) {
      const int sx = std::min(x * size.x / std::max(rect[2], 1), size.x - 1);
      const int dx = rect[0] + x, dy = rect[1] + y;
      if (dx < 0 || dy < 0 || dx >= into.width || dy >= into.height) continue;
      std::uint8_t* d = &into.rgba[(static_cast<std::size_t>(dy) * into.width + dx) * 4];
      const std::uint8_t* src = &rows[(static_cast<std::size_t>(sy) * size.x + sx) * 4];
      d[0] = src[0];
      d[1] = src[1];
      d[2] = src[2];
      d[3] = 255;
    }
  }
}

ViewerScene::PaneProjection ViewerScene::paneProjection(int p, double w, double h) const {
  const render::Camera& cam = camera(p);
  return {cam.projection(w / std::max(h, 1.0)) * cam.view(), w, h};
}

const session::MaskSurface& ViewerScene::maskSurface(const surfaces::Region& r) const {
  bool found = false;
  MaskShape& hit = cacheSlot(maskShapes_, nextMaskShape_, kMaskOutlineCache,
                             [&](const MaskShape& m) { return m.mask == r.mask; }, found);
  if (!found) {
    hit.mask = r.mask;
    session::maskSurface(r, hit.surface);
  }
  return hit.surface;
}

void ViewerScene::drawRegions3d(Image& img, int p) const {
  // As the window draws them over a 3D pane: a sphere as its silhouette's translucent disc with an outline, a
  // box as the outlines of its faces, a mask as the creases of its voxels' surface (or, past
  // session::kMaskFaceCap faces, the box of its bounds); over the scene, not depth-tested.
  const session::ViewerState& st = state();
  if (st.roiSet.regions.empty()) return;
  const auto rect = paneRect(p);
  const PaneProjection toPane = paneProjection(p, rect[2], rect[3]);
  auto project = [&](const glm::dvec3& world, glm::dvec2& out) {
    if (!toPane(world, out)) return false;
    out += glm::dvec2(rect[0], rect[1]);
    return true;
  };
  const render::Camera& cam = camera(p);
  render::ImageCanvas canvas(img);
  const glm::dvec3 up = glm::normalize(glm::cross(cam.right(), cam.forward()));
  std::vector<glm::dvec2> poly;
  for (std::size_t i = 0; i < st.roiSet.regions.size(); ++i) {
    if (i < st.roiVisible.size() && !st.roiVisible[i]) continue;
    const surfaces::Region& r = st.roiSet.regions[i];
    const glm::u8vec3 k = session::regionKindColour(r.kind);
    if (r.shape == surfaces::RegionShape::Sphere) {
      glm::dvec2 c, top;
      if (!project(r.centre, c) || !project(r.centre + r.radius * up, top)) continue;
      const double radius = glm::length(top - c);
      for (int y = std::max(rect[1], int(std::ceil(c.y - radius)));
           y < std::min(rect[1] + rect[3], int(c.y + radius)); ++y) {
        const double dy = y + 0.5 - c.y, half = std::sqrt(std::max(radius * radius - dy * dy, 0.0));
        const int x0 = std::max(rect[0], int(std::lround(c.x - half))),
                  x1 = std::min(rect[0] + rect[2], int(std::lround(c.x + half)));
        if (x1 > x0) canvas.blend(x0, y, x1 - x0, 1, k.x, k.y, k.z, 60);
      }
      poly.clear();
      for (int j = 0; j < 48; ++j)
        poly.push_back(c + radius * glm::dvec2(std::cos(2 * M_PI * j / 48), std::sin(2 * M_PI * j / 48)));
      drawOutline(img, poly, rect, k);
    } else {
      glm::dvec3 lo = r.lo, hi = r.hi;
      if (r.shape == surfaces::RegionShape::Mask) {
        const session::MaskSurface& s = maskSurface(r);
        if (s.drawn) {
          poly.clear();
          glm::dvec2 a, b;
          for (std::size_t j = 0; j + 1 < s.creases.size(); j += 2)
            if (project(s.creases[j], a) && project(s.creases[j + 1], b)) poly.push_back(a), poly.push_back(b);
          drawOutline(img, poly, rect, k, true);
          continue;
        }
        lo = s.lo, hi = s.hi;
      }
      glm::dvec2 q[8];
      bool ok = true;
      for (int j = 0; j < 8; ++j)
        ok &= project(session::boxCorner(lo, hi, j), q[j]);
      if (!ok) continue;
      for (const auto& f : session::kBoxFaces) {
        poly.assign({q[f[0]], q[f[1]], q[f[2]], q[f[3]]});
        drawOutline(img, poly, rect, k);
      }
    }
  }
}

Image ViewerScene::layoutImage() const {
  Image img(width_, height_);
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
  if (!session_.mesh()) return img;
  for (int p = 0; p < paneCount(); ++p) {
    readPane(outputFbo_[p], outputSize_[p], paneRect(p), img);
    drawRegions3d(img, p);
  }
  if (!state().ortho) {
    render::ImageCanvas canvas(img);
    drawFurniture(canvas);
    if (paneCount() == 2) render::drawPaneDivider(img, paneRect(1)[0]); // as the window draws it
    return img;
  }
  const glm::dvec3 cross = state().crosshair;
  for (int s = 0; s < 3; ++s) {
    const auto r = orthoRect(s);
    if (orthoRenderers_[s] && !orthoMeshes_[s].empty())
      readPane(orthoRenderers_[s]->output().id(), {r[2], r[3]}, r, img);
    // The regions' outlines where they cut the slice, in their kind's colour.
    std::vector<glm::dvec2> outline;
    bool segments = false;
    for (std::size_t i = 0; i < state().roiSet.regions.size(); ++i)
      if (regionOutlinePixels(s, i, outline, &segments))
        drawOutline(img, outline, r, session::regionKindColour(state().roiSet.regions[i].kind), segments);
    // The crosshair: a horizontal and a vertical line through its point, clipped to the pane.
    const glm::dvec2 c = orthoPixel(s, cross);
    const int cx = static_cast<int>(std::floor(c.x)), cy = static_cast<int>(std::floor(c.y));
    if (cy >= r[1] && cy < r[1] + r[3]) render::fillRect(img, r[0], cy, r[2], 1, 255, 230, 90);
    if (cx >= r[0] && cx < r[0] + r[2]) render::fillRect(img, cx, r[1], 1, r[3], 255, 230, 90);
    // Orientation letters at the middle of each edge.
    const render::Camera& cam = orthoCameras_[s];
    const glm::dvec3 right = cam.right(), up = glm::normalize(glm::cross(right, cam.forward()));
    const render::FontSize font = render::letterFont(r[2], r[3]);
    const int scale = 2, th = render::textHeight(font);
    const auto letter = [&](const glm::dvec3& d, int x, int y) {
      const std::string t = session::anatomicalLabel(d);
      // On a black box: the crosshair through the pane's middle would run through the letter.
      const int tw = render::textWidth(t, font), x0 = x - tw / 2, y0 = y - th / 2;
      render::fillRect(img, x0 - scale, y0 - scale, tw + 2 * scale, th + 2 * scale, 0, 0, 0);
      render::drawText(img, x0, y0, t, font, 255, 230, 90);
    };
    letter(right, r[0] + r[2] - 10, r[1] + r[3] / 2);
    letter(-right, r[0] + 10, r[1] + r[3] / 2);
    letter(up, r[0] + r[2] / 2, r[1] + 10);
    letter(-up, r[0] + r[2] / 2, r[1] + r[3] - 10);
  }
  render::ImageCanvas canvas(img);
  drawFurniture(canvas);
  // Pane borders.
  const int w2 = std::max(width_ / 2, 1), h2 = std::max(height_ / 2, 1);
  render::fillRect(img, w2 - 1, 0, 2, height_, 90, 90, 90);
  render::fillRect(img, 0, h2 - 1, width_, 2, 90, 90, 90);
  return img;
}

void ViewerScene::probe(double x, double y) {
  session_.clearProbe();
  if (!session_.mesh() || !session_.dataset()) return;
  const int p = paneAt(x);
  const auto rect = paneRect(p);
  if (!outputFbo_[p] || !outputRenderer_[p] || rect[2] < 1 || rect[3] < 1) return;
  if (x < rect[0] || y < rect[1]) return; // the ortho layout's slice panes
  // Pixel of the output target (smaller than the pane after an interactive frame), y up.
  const glm::ivec2 size = outputSize_[p];
  const int px = static_cast<int>((x - rect[0]) * size.x / rect[2]);
  const int py = size.y - 1 - static_cast<int>((y - rect[1]) * size.y / rect[3]);
  if (px < 0 || py < 0 || px >= size.x || py >= size.y) return;
  float depth = 1.0f;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, outputFbo_[p]);
  glReadPixels(px, py, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (!(depth < 1.0f)) return;
  // Unproject through the guarded target the renderer drew with (its depth is the output's depth).
  const render::FrameView& v = outputRenderer_[p]->frameView();
  const glm::dvec4 ndc(2.0 * (px + v.guard + 0.5) / v.target.x - 1.0,
                       2.0 * (py + v.guard + 0.5) / v.target.y - 1.0, 2.0 * depth - 1.0, 1.0);
  const glm::dvec4 w = glm::inverse(glm::dmat4(v.viewProj)) * ndc;
  if (std::abs(w.w) < 1e-12) return;
  session_.probeAt(glm::dvec3(w) / w.w);
}

void ViewerScene::tractFrame(int p, bool fabricChanged, bool moving) {
  session::ViewerState& state = session_.state();
  render::FabricRenderer& r = *outputRenderer_[p];
  const int slot = &r == lowRes_[p].get() ? 2 + p : p;
  if (!tractLayers_[slot]) tractLayers_[slot] = std::make_unique<render::TractLayer>();
  render::TractLayer& layer = *tractLayers_[slot];
  tractLayer_[p] = &layer;
  const auto rect = paneRect(p);
  render::TractLayer::Frame f;
  f.fabric = &r.output();
  f.fabricChanged = fabricChanged;
  f.view = r.frameView();
  // The width on screen: an interactive frame is magnified by the blit.
  f.style.widthPx = static_cast<float>(state.tractWidthPx * outputSize_[p].x / std::max(rect[2], 1));
  session::TractPick pick;
  if (session_.tractsSlab()) pick.plane = session_.tractsPlane();
  session::TractOverlayOptions overlay;
  overlay.nearMm = state.tractsNearMm;
  overlay.clipMm = state.tractsClipMm;
  overlay.clipDepthMm = state.tractsClipOffsetMm;
  const session::TractClip clip =
      session::tractClip(pick, overlay, glm::vec3(camera(p).forward()), session_.meshCentre());
  f.style.plane = clip.plane;
  f.style.slabMm = clip.slabMm;
  f.style.highlightNode = highlightedNode();
  f.key = tractKeys_[p] = tractKey();
  f.moving = moving;
  f.draw = tractBudget_.choose(*tractRenderer_);
  f.chunk = tractBudget_.chunk();
  layer.frame(*tractRenderer_, f);
  int level = 0;
  std::size_t segments = 0;
  double ms = 0;
  while (layer.takeTiming(level, segments, ms))
    tractBudget_.measured(level, segments, ms);
  state.tractsLevel = layer.shownLevel();
  const std::size_t all = tractRenderer_->segmentCount(layer.shownLevel());
  state.tractsLevelFraction =
      all ? static_cast<double>(layer.shownSegments()) / static_cast<double>(all) : 1.0;
}

void ViewerScene::applyKey(session::Key key) {
  session::ActionList actions;
  session::keyActions(key, state(), actions);
  for (const auto& a : actions)
    apply(a);
}

void ViewerScene::apply(const session::Action& action) {
  session_.apply(action);
  try {
    if (applyView(action) || !std::holds_alternative<session::SetFabricParams>(action)) return;
    dataChanged(); // new fabric parameters: the panes start again
  } catch (...) {
    session_.setError(currentExceptionMessage());
  }
}

bool ViewerScene::applyView(const session::Action& action) {
  session::ViewerState& state = session_.state();
  return std::visit(
      [&](const auto& a) {
        using T = std::decay_t<decltype(a)>;
        if constexpr (std::is_same_v<T, session::SetView>) {
          setView(a.view);
        } else if constexpr (std::is_same_v<T, session::SetNeurological>) {
          state.neurological = a.on;
          using V = render::StandardView;
          if (state.view == V::Axial || state.view == V::Coronal || state.view == V::Sagittal)
            setView(state.view);
        } else if constexpr (std::is_same_v<T, session::SetSplit>) {
          if (a.mode && *a.mode != state.secondPane) {
            state.secondPane = *a.mode;
            dataChanged();
          }
          if (a.on == state.split) return true;
          state.split = a.on;
          if (a.on) cameras_[1] = cameras_[0];
          if (const auto data = session_.dataset())
            for (int p = 0; p < 2; ++p)
              cameras_[p].fit(data->lo, data->hi, paneAspect(p));
          activePane_ = 0;
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::SetLinkedCameras>) {
          state.linked = a.on;
          cameras_[1] = cameras_[0];
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::SetSecondPane>) {
          state.secondPane = a.mode;
          dataChanged();
        } else if constexpr (std::is_same_v<T, session::SetOrtho>) {
          if (a.on == state.ortho) return true;
          state.ortho = a.on;
          const auto data = session_.dataset();
          if (a.on && data && state.crosshair == glm::dvec3(0.0)) state.crosshair = 0.5 * (data->lo + data->hi);
          orthoCameraKey_ = {0, 0, -1};
          orthoDirty_.fill(true);
          if (data) cameras_[0].fit(data->lo, data->hi, paneAspect(0));
          activePane_ = 0;
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::SetCrosshair>) {
          const auto data = session_.dataset();
          if (!data) throw UsageError("load data before placing the crosshair");
          state.crosshair = glm::clamp(a.world, data->lo, data->hi);
          if (state.ortho) updateOrtho();
        } else if constexpr (std::is_same_v<T, session::RecordMovie>) {
          if (recording_) throw UsageError("a movie is already being recorded");
          if (session_.mayWrite(a.path, a.force, action)) startRecording(a);
        } else if constexpr (std::is_same_v<T, session::SetBackground>) {
          backgroundAsked_ = a;
          ++backgroundSerial_;
          resolveBackground();
        } else if constexpr (std::is_same_v<T, session::SetFabricAlong>) {
          if (a.mm && !(std::isfinite(*a.mm) && *a.mm > 0 && *a.mm <= 1000))
            throw UsageError("the fabric along the tracts needs a distance in (0, 1000] mm, not " +
                             std::to_string(*a.mm));
          if (a.on) state.fabricAlong = *a.on;
          if (a.mm) state.fabricAlongMm = *a.mm;
          updateAlong();
        } else if constexpr (std::is_same_v<T, session::SetProfile>) {
          if (a.scalar && *a.scalar != "fa" && *a.scalar != "md" && *a.scalar != "ad" && *a.scalar != "rd") {
            // NAME=IMAGE, as `dtfabric profile --scalar`: the image is read on the worker.
            if (a.scalar->find('=') == std::string::npos)
              throw UsageError("the profile takes fa, md, ad, rd or NAME=IMAGE, not '" + *a.scalar + "'");
            const session::ScalarSpec spec = session::parseScalarSpec(*a.scalar);
            if (!std::filesystem::is_regular_file(spec.image))
              throw InputError(spec.image + ": no such file (the profile's scalar '" + spec.name + "')");
          }
          const bool was = state.profile.on;
          if (a.on) state.profile.on = *a.on;
          if (a.scalar) state.profile.scalar = *a.scalar;
          if (state.profile.on != was) session_.reapplyTractChoice(); // each point's node, or none
          updateProfile();
        } else if constexpr (std::is_same_v<T, session::HoverProfileNode>) {
          session::ViewerState::Profile& pr = state.profile;
          if (a.node >= static_cast<int>(pr.core.size()))
            throw UsageError("the profile has " + std::to_string(pr.core.size()) + " nodes, not node " +
                             std::to_string(a.node));
          pr.hovered = a.pin ? -1 : a.node;
          if (a.pin && a.node >= 0) pr.pinned = pr.pinned == a.node ? -1 : a.node;
          profileCrosshair();
        } else if constexpr (std::is_same_v<T, session::SetFurniture>) {
          if (a.legend) state.legend = *a.legend;
          if (a.scaleBar) state.scaleBar = *a.scaleBar;
          if (a.colourBar) state.colourBar = *a.colourBar;
        } else if constexpr (std::is_same_v<T, session::ResetView>) {
          setView(session_.homeView());
        } else if constexpr (std::is_same_v<T, session::Rotate>) {
          const auto rect = paneRect(a.pane < 0 ? activePane_ : a.pane);
          const double s = std::max(std::min(rect[2], rect[3]), 1);
          // Arcball from the pane centre in steps of <= 10 pixels, like a real drag.
          const int n =
              std::max(1, static_cast<int>(std::ceil(std::max(std::abs(a.dx), std::abs(a.dy)) / 10.0)));
          render::Camera& cam = cameraFor(a.pane);
          for (int i = 0; i < n; ++i)
            cam.trackball({0.0, 0.0}, {2.0 * a.dx / n / s, -2.0 * a.dy / n / s});
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::Pan>) {
          const auto rect = paneRect(a.pane < 0 ? activePane_ : a.pane);
          render::Camera& cam = cameraFor(a.pane);
          const double dist = glm::length(cam.target - cam.eye);
          const double halfH =
              cam.orthographic ? cam.orthoHalfHeight : dist * std::tan(0.5 * glm::radians(cam.fovYDeg));
          const double mmPerPixel = 2.0 * halfH / std::max(rect[3], 1);
          const glm::dvec3 right = cam.right(), up = glm::normalize(glm::cross(right, cam.forward()));
          const glm::dvec3 shift = (-a.dx * right + a.dy * up) * mmPerPixel;
          cam.eye += shift;
          cam.target += shift;
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::Zoom>) {
          if (a.factor > 0) cameraFor(a.pane).zoom(1.0 / a.factor);
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::SaveCamera>) {
          if (session_.mayWrite(a.path, a.force, action)) writeCameraFile(a.path, cameraFor(-1));
        } else if constexpr (std::is_same_v<T, session::ConfirmOverwrite>) {
          // Screenshots are the window's: it answers the prompt itself and takes them.
          if (auto forced = session_.answerOverwrite(a.overwrite);
              forced && !std::holds_alternative<session::Screenshot>(*forced))
            apply(*forced);
        } else if constexpr (std::is_same_v<T, session::SetCamera>) {
          cameraFor(a.pane) = a.camera;
          if (state.linked) cameras_[1] = cameras_[0];
          cameraChanged();
        } else if constexpr (std::is_same_v<T, session::LoadCamera>) {
          cameraFor(-1) = readCameraFile(a.path);
          if (state.linked) cameras_[1] = cameras_[0];
          cameraChanged();
        } else {
          return false; // the session's (or the window's: Screenshot, Quit)
        }
        return true;
      },
      action);
}

void writeCameraFile(const std::string& path, const render::Camera& c) {
  if (path.empty()) throw InputError("camera file: no path given");
  io::AtomicOutput file(path); // a failed write leaves any earlier camera file as it was
  std::ofstream out(file.tempPath());
  if (!out) throw InputError(path + ": cannot write the camera file");
  out.precision(17);
  out << "dtfabric-camera 1\n"
      << "eye " << c.eye.x << " " << c.eye.y << " " << c.eye.z << "\n"
      << "target " << c.target.x << " " << c.target.y << " " << c.target.z << "\n"
      << "up " << c.up.x << " " << c.up.y << " " << c.up.z << "\n"
      << "orthographic " << (c.orthographic ? 1 : 0) << "\n"
      << "fov " << c.fovYDeg << "\nhalf-height " << c.orthoHalfHeight << "\n"
      << "near " << c.nearPlane << "\nfar " << c.farPlane << "\n";
  out.close();
  if (!out) throw InputError(path + ": cannot write the camera file");
  file.commit();
}

render::Camera readCameraFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the camera file");
  std::string magic;
  int version = 0;
  in >> magic >> version;
  if (magic != "dtfabric-camera" || version != 1) throw InputError(path + ": not a dtfabric camera file");
  render::Camera c;
  std::string key;
  while (in >> key) {
    auto vec = [&](glm::dvec3& v) { in >> v.x >> v.y >> v.z; };
    if (key == "eye")
      vec(c.eye);
    else if (key == "target")
      vec(c.target);
    else if (key == "up")
      vec(c.up);
    else if (key == "orthographic")
      in >> c.orthographic;
    else if (key == "fov")
      in >> c.fovYDeg;
    else if (key == "half-height")
      in >> c.orthoHalfHeight;
    else if (key == "near")
      in >> c.nearPlane;
    else if (key == "far")
      in >> c.farPlane;
    else
      throw InputError(path + ": unknown camera key '" + key + "'");
    if (!in) throw InputError(path + ": bad value for '" + key + "'");
  }
  auto finiteVec = [](const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  const bool finite = finiteVec(c.eye) && finiteVec(c.target) && finiteVec(c.up);
  if (!finite || glm::length(c.target - c.eye) <= 0 || glm::length(c.up) <= 0 || c.orthoHalfHeight <= 0 ||
      c.nearPlane <= 0 || c.farPlane <= c.nearPlane || c.fovYDeg <= 0 || c.fovYDeg >= 180)
    throw InputError(path + ": degenerate camera");
  return c;
}

} // namespace dtf::app
