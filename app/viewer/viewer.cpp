#include "app/viewer/viewer.h"

#include "app/scene/tensor_input.h"
#include "app/scene/tract_colouring.h"
#include "app/scene/tract_files.h"
#include "app/scene/tract_overlay.h"
#include "io/atomic_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/model/tensor.h"
#include "render/gl_context.h"
#include "surfaces/slices.h"
#include "ui/panels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <epoxy/gl.h>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_inverse.hpp>
#include <sstream>

namespace dtf::app {

namespace {

constexpr int kStillIterations = 12;    // advection iterations per frame once the camera is still
constexpr double kMotionSeconds = 0.15; // a camera change keeps frames interactive this long
constexpr double kTargetFrameMs = 66;   // interactive frame time the resolution adapts to (15 fps)
constexpr std::size_t kMaxRecent = 8;
const char* const kAxisNames[3] = {"axial", "coronal", "sagittal"};

ui::SurfaceKind sliceKind(int axis) {
  return axis == 0   ? ui::SurfaceKind::Axial
         : axis == 1 ? ui::SurfaceKind::Coronal
                     : ui::SurfaceKind::Sagittal;
}

render::StandardView homeViewFor(ui::SurfaceKind k) {
  switch (k) {
  case ui::SurfaceKind::Axial:
    return render::StandardView::Axial;
  case ui::SurfaceKind::Coronal:
    return render::StandardView::Coronal;
  case ui::SurfaceKind::Sagittal:
    return render::StandardView::Sagittal;
  default: // curved surfaces: the display convention's axial view, as `dtfabric render --view axial`
    return render::StandardView::Axial;
  }
}

} // namespace

ViewerScene::ViewerScene(const std::string& surface) : initialSurface_(surface) {
  for (auto& r : renderers_)
    r = std::make_unique<render::FabricRenderer>();
  for (auto& r : lowRes_)
    r = std::make_unique<render::FabricRenderer>();
  if (!surface.empty()) {
    try {
      applySpec(parseSurfaceSpec(surface));
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
}

ViewerScene::~ViewerScene() = default;

void ViewerScene::setError(const std::string& message) {
  state_.errorChain = ui::splitErrorChain(message);
  ++errorSerial_;
}

void ViewerScene::addInput(const std::string& path) {
  if (!path.empty() && std::find(inputs_.begin(), inputs_.end(), path) == inputs_.end())
    inputs_.push_back(path);
}

bool ViewerScene::mayWrite(const std::string& path, bool force, const ui::Action& action) {
  try {
    io::refuseOverwritingInput(path, inputs_);
    std::error_code ec;
    if (force || !std::filesystem::exists(path, ec)) return true;
    if (!askBeforeOverwrite_)
      throw InputError(path + " exists (use --force to overwrite it: `view --force`, or a script line's "
                              "--force before the path)");
    pendingOverwrite_ = action;
    state_.overwritePath = path;
  } catch (...) {
    setError(currentExceptionMessage());
  }
  return false;
}

std::optional<ui::Action> ViewerScene::answerOverwrite(bool overwrite) {
  std::optional<ui::Action> a;
  a.swap(pendingOverwrite_);
  state_.overwritePath.clear();
  if (!a || !overwrite) return std::nullopt;
  if (auto* shot = std::get_if<ui::Screenshot>(&*a)) shot->force = true;
  if (auto* cam = std::get_if<ui::SaveCamera>(&*a)) cam->force = true;
  if (auto* tracts = std::get_if<ui::SaveTracts>(&*a)) tracts->force = true;
  return a;
}

void ViewerScene::addRecent(const std::string& path) {
  auto& r = state_.recent;
  r.erase(std::remove(r.begin(), r.end(), path), r.end());
  r.insert(r.begin(), path);
  if (r.size() > kMaxRecent) r.resize(kMaxRecent);
}

bool ViewerScene::settled() const {
  return !worker_.busy() && !state_.busy && !state_.tractsLoading && !tractWorker_.busy() &&
         !pendingAgreement_;
}

bool ViewerScene::converged() const {
  for (int p = 0; p < paneCount(); ++p) {
    if (dirty_[p] && hasMesh_) return false;
    if (paneShowsTracts(p) && hasMesh_ &&
        (!tractLayer_[p] || !tractLayer_[p]->complete() || tractKeys_[p] != tractKey()))
      return false;
  }
  return true;
}

bool ViewerScene::paneShowsTracts(int p) const {
  if (!state_.tractsVisible || !tractRenderer_ || tractRenderer_->segmentCount(0) == 0) return false;
  return !(state_.split && state_.secondPane == ui::SecondPane::Tracts && p == 0);
}

std::array<int, 4> ViewerScene::paneRect(int p) const {
  if (!state_.split) return {0, 0, width_, height_};
  const int half = std::max(width_ / 2, 1);
  return p == 0 ? std::array<int, 4>{0, 0, half, height_}
                : std::array<int, 4>{half, 0, std::max(width_ - half, 1), height_};
}

int ViewerScene::paneAt(double x) const {
  return state_.split && x >= paneRect(1)[0] ? 1 : 0;
}

double ViewerScene::paneAspect(int p) const {
  auto r = paneRect(p);
  return static_cast<double>(r[2]) / std::max(r[3], 1);
}

render::Camera& ViewerScene::cameraFor(int pane) {
  if (state_.linked) return cameras_[0];
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
  state_.converged = false;
}

void ViewerScene::setView(render::StandardView v) {
  state_.view = v;
  if (!data_) return;
  for (int p = 0; p < 2; ++p) {
    if (!state_.linked && p != activePane_) continue;
    cameras_[p] = render::Camera::standard(v, data_->lo, data_->hi, paneAspect(p), state_.neurological);
  }
  if (state_.linked) cameras_[1] = cameras_[0];
  cameraChanged();
}

SurfaceSpec ViewerScene::currentSpec() const {
  SurfaceSpec s;
  const int axis = ui::sliceAxisOf(state_.surface);
  if (state_.surface == ui::SurfaceKind::FaIsosurface) {
    s.kind = SurfaceSpec::Kind::Fa;
    s.value = state_.faThreshold;
    s.text = "fa=" + std::to_string(state_.faThreshold);
  } else if (axis >= 0) {
    s.kind = SurfaceSpec::Kind::Slice;
    s.axis = kAxisNames[axis];
    s.index = data_ ? state_.slice[axis] : -1;
    s.text = "slice=" + s.axis;
  } else {
    s = otherSpec_;
  }
  return s;
}

void ViewerScene::applySpec(const SurfaceSpec& spec) {
  switch (spec.kind) {
  case SurfaceSpec::Kind::Fa:
    state_.surface = ui::SurfaceKind::FaIsosurface;
    state_.faThreshold = spec.value;
    break;
  case SurfaceSpec::Kind::Slice: {
    const int axis = static_cast<int>(surfaces::parseSliceAxis(spec.axis));
    state_.surface = sliceKind(axis);
    if (spec.index >= 0) state_.slice[axis] = std::min(spec.index, std::max(state_.sliceCount[axis] - 1, 0));
    break;
  }
  case SurfaceSpec::Kind::Fibre: {
    state_.surface = ui::SurfaceKind::Fibre;
    otherSpec_ = spec;
    // The Surface panel edits the seed line in voxel indices.
    glm::dvec3 a = spec.a, b = spec.b;
    if (!spec.voxelCoords && data_) {
      a = data_->loaded.field.grid.toVoxel(a);
      b = data_->loaded.field.grid.toVoxel(b);
    }
    if (spec.voxelCoords || data_) {
      const glm::ivec3 ia(glm::round(a)), ib(glm::round(b));
      state_.fibreSeed = {ia.x, ia.y, ia.z, ib.x, ib.y, ib.z};
      ++state_.fibreSeedSerial;
    }
    break;
  }
  default:
    state_.surface = ui::SurfaceKind::Other;
    otherSpec_ = spec;
    break;
  }
}

void ViewerScene::replaceField(TensorField field) {
  if (!data_ || field.grid.dims != data_->loaded.field.grid.dims) return;
  auto d = std::make_shared<ViewerDataset>();
  d->path = data_->path;
  d->loaded = data_->loaded;
  d->loaded.field = std::move(field);
  d->fa = data_->fa;
  d->sweeper = data_->sweeper;
  d->buildOptions = data_->buildOptions;
  d->lo = data_->lo;
  d->hi = data_->hi;
  data_ = std::move(d);
  ++fieldSerial_;
  dataChanged();
  requestSurface();
}

void ViewerScene::requestSurface() {
  if (!data_) return;
  if ((state_.surface == ui::SurfaceKind::Fibre && otherSpec_.kind != SurfaceSpec::Kind::Fibre) ||
      (state_.surface == ui::SurfaceKind::Other && otherSpec_.text.empty()))
    return; // waits for a seed line / spec
  latestSurface_ = nextId_++;
  state_.surfacePending = true;
  worker_.requestSurface(latestSurface_, data_, currentSpec());
}

void ViewerScene::loadFile(const ui::LoadFile& a) {
  const io::TensorLayout layout = io::parseLayout(a.layout.empty() ? "auto" : a.layout);
  SurfaceSpec first = currentSpec();
  if (first.kind == SurfaceSpec::Kind::Slice && !data_) {
    // A slice index from the command line is kept; the viewer clamps it once the grid is known.
    if (!initialSurface_.empty()) first = parseSurfaceSpec(initialSurface_);
  } else if (first.kind == SurfaceSpec::Kind::Slice) {
    first.index = -1; // a new grid: start in the middle
  }
  if ((first.kind == SurfaceSpec::Kind::Fibre || first.kind == SurfaceSpec::Kind::Mesh ||
       first.kind == SurfaceSpec::Kind::Iso || first.kind == SurfaceSpec::Kind::Plane) &&
      first.text.empty()) {
    first = parseSurfaceSpec("fa=0.25");
  }
  addInput(a.path);
  addInput(gradientSibling(a.path, ".bval"));
  addInput(gradientSibling(a.path, ".bvec"));
  latestLoad_ = nextId_++;
  latestSurface_ = latestLoad_;
  state_.busy = true;
  state_.busyStage = "reading " + a.path;
  busySince_ = std::chrono::steady_clock::now();
  worker_.requestLoad(latestLoad_, a.path, layout, first);
}

render::FabricRenderer& ViewerScene::upToDate(std::unique_ptr<render::FabricRenderer>& r, int slot) {
  if (data_ && fieldUploaded_[slot] != fieldSerial_) {
    r->setField(data_->loaded.field);
    fieldUploaded_[slot] = fieldSerial_;
  }
  if (hasMesh_ && meshUploaded_[slot] != meshSerial_) {
    r->setMesh(*mesh_);
    meshUploaded_[slot] = meshSerial_;
  }
  return *r;
}

void ViewerScene::setMesh(Mesh&& mesh) {
  // Uploaded when a renderer next draws: a sweep without split view feeds one or two renderers, not four.
  mesh_ = std::make_shared<const Mesh>(std::move(mesh));
  hasMesh_ = true;
  ++meshSerial_;
  glm::vec3 lo, hi;
  mesh_->bounds(lo, hi);
  meshCentre_ = 0.5f * (lo + hi);
  state_.triangles = mesh_->triangleCount();
  cameraChanged(); // a new mesh while sweeping counts as motion: interactive frames, not still refinement
  requestSelection();
}

void ViewerScene::onResult(WorkerResult& r) {
  using K = WorkerResult::Kind;
  if (r.id < latestLoad_) return; // belongs to data already replaced
  if (r.kind == K::Loaded) {
    data_ = r.data;
    const ViewerDataset& d = *data_;
    const TensorField& f = d.loaded.field;
    state_.busy = false;
    state_.hasData = true;
    ui::DataInfo& info = state_.data;
    info.path = d.path;
    info.layout = io::layoutName(d.loaded.layout);
    info.layoutReason = d.loaded.layoutReason;
    info.orientation = f.grid.orientationCode();
    info.dims = f.grid.dims;
    info.spacing = f.grid.spacing;
    info.validVoxels = static_cast<std::size_t>(std::count(f.valid.begin(), f.valid.end(), 1));
    info.warnings = d.loaded.warnings;
    for (int a = 0; a < 3; ++a) {
      state_.sliceCount[a] = surfaces::sliceCount(f.grid, static_cast<surfaces::SliceAxis>(a));
      state_.slice[a] = state_.sliceCount[a] / 2;
    }
    applySpec(r.spec);
    if (r.spec.kind == SurfaceSpec::Kind::Slice && r.spec.index < 0) {
      const int axis = ui::sliceAxisOf(state_.surface);
      state_.slice[axis] = state_.sliceCount[axis] / 2;
    }
    ++fieldSerial_;
    hasField_ = true;
    hasMesh_ = false;
    state_.surfacePending = false;
    state_.surfaceText = describeSurface(currentSpec());
    if (!r.mesh.empty())
      setMesh(std::move(r.mesh));
    else if (!r.error.empty())
      setError(r.error);
    else
      state_.surfaceText += ": empty";
    addRecent(d.path);
    homeView_ = homeViewFor(state_.surface);
    setView(homeView_);
    return;
  }
  if (r.id == latestLoad_ && r.kind == K::Failed) {
    state_.busy = false;
    setError(r.error);
    return;
  }
  state_.surfacePending = r.id < latestSurface_;
  if (r.kind == K::Failed) {
    setError("while building the " + describeSurface(r.spec) + ": " + r.error);
    return;
  }
  state_.surfaceText = describeSurface(r.spec);
  if (r.mesh.empty()) {
    state_.surfaceText += ": empty (previous surface shown)";
    return;
  }
  setMesh(std::move(r.mesh));
}

void ViewerScene::update() {
  WorkerResult r;
  while (worker_.poll(r)) {
    try {
      onResult(r);
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
  if (state_.tractsLoading && tractsLoading_.valid() &&
      tractsLoading_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    state_.tractsLoading = false;
    try {
      setTracts(std::make_shared<const Polylines>(tractsLoading_.get()), pendingTractPath_);
      logInfo(state_.tractPath + ": " + std::to_string(state_.tractCount) + " streamlines, " +
              std::to_string(state_.tractPoints) + " points");
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
  TractResult tr;
  while (tractWorker_.poll(tr)) {
    try {
      onTractResult(tr);
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
  if (state_.tracking) tractWorker_.tracking(&state_.trackSeedsDone, &state_.trackProgress);
  if (pendingAgreement_ && !state_.busy && !state_.surfacePending && !state_.tractsLoading) {
    const ui::ComputeAgreement a = *pendingAgreement_;
    pendingAgreement_.reset();
    try {
      startAgreement(a);
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
  state_.agreementRunning = pendingAgreement_.has_value() || tractWorker_.agreementRunning();
  if (state_.busy) {
    worker_.loading(&state_.busyStage);
    state_.busySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - busySince_).count();
  }
}

void ViewerScene::render(int width, int height) {
  width = std::max(width, 1);
  height = std::max(height, 1);
  if (width != width_ || height != height_) {
    width_ = width;
    height_ = height;
    dataChanged();
  }
  if (!hasMesh_ || !hasField_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool moving =
      interacting_ || std::chrono::duration<double>(now - lastMotion_).count() < kMotionSeconds;
  if (moving && state_.frameMs > 0 && interactiveScale_ < 1.0) {
    const double wanted = scale_ * std::clamp(std::sqrt(kTargetFrameMs / state_.frameMs), 0.7, 1.3);
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
      if (p == 1 && state_.secondPane == ui::SecondPane::Phong) {
        r.renderPhong(cam);
        outputFbo_[p] = r.output().id();
        dirty_[p] = low;
        continue;
      }
      render::FabricParams params = state_.fabric;
      if (p == 1 && state_.secondPane == ui::SecondPane::OtherColourMode)
        params.colour = params.colour == render::ColourMode::Medical ? render::ColourMode::Engineering
                                                                     : render::ColourMode::Medical;
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
      // Still: refine until almost no covered pixel changes by more than epsilon (the renderStill rule).
      if (covered_[p] == 0) covered_[p] = std::max(r.coveredPixels(), 1u);
      if (r.changedPixels() <= params.stillChangedFraction * covered_[p] ||
          iterationsSinceRestart_[p] >= std::max(params.stillMaxIterations, kStillIterations))
        dirty_[p] = false;
    }
    for (int p = 0; p < paneCount(); ++p)
      if (tractsShown_[p] && outputRenderer_[p] && outputFbo_[p]) tractFrame(p, fabricChanged[p], moving);
    static const std::string where = "rendering the fabric"; // no allocation per frame
    render::checkGl(where);
  } catch (...) {
    dirty_.fill(false); // do not repeat a failing frame every frame
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
    setError("while rendering: " + currentExceptionMessage());
  }
  state_.converged = converged();
}

void ViewerScene::present(unsigned fbo, int x, int y) {
  for (int p = 0; p < paneCount(); ++p) {
    if (!outputFbo_[p] || !hasMesh_) continue;
    const auto rect = paneRect(p);
    const glm::ivec2 src = outputSize_[p];
    const bool same = src.x == rect[2] && src.y == rect[3];
    glBlitNamedFramebuffer(outputFbo_[p], fbo, 0, 0, src.x, src.y, x + rect[0], y, x + rect[0] + rect[2],
                           y + rect[3], GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  }
}

void ViewerScene::probe(double x, double y) {
  ui::ProbeInfo& out = state_.probe;
  out.onSurface = out.inData = false;
  if (!hasMesh_ || !data_) return;
  const int p = paneAt(x);
  const auto rect = paneRect(p);
  if (!outputFbo_[p] || !outputRenderer_[p] || rect[2] < 1 || rect[3] < 1) return;
  // Pixel of the output target (smaller than the pane after an interactive frame), y up.
  const glm::ivec2 size = outputSize_[p];
  const int px = static_cast<int>((x - rect[0]) * size.x / rect[2]);
  const int py = size.y - 1 - static_cast<int>(y * size.y / rect[3]);
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
  out.onSurface = true;
  out.world = glm::dvec3(w) / w.w;
  const TensorField& f = data_->loaded.field;
  const glm::dvec3 ijk = glm::round(f.grid.toVoxel(out.world));
  out.voxel = glm::ivec3(ijk);
  if (!f.grid.contains(out.voxel.x, out.voxel.y, out.voxel.z)) return;
  const std::size_t i = f.grid.index(out.voxel.x, out.voxel.y, out.voxel.z);
  if (!f.valid[i]) return;
  const EigenSystem e = eigenDecompose(f.tensors[i]);
  out.inData = true;
  out.fa = fractionalAnisotropy(e.values);
  out.eigenvalues = e.values;
  out.e1 = e.vectors[0];
}

void ViewerScene::setTracts(std::shared_ptr<const Polylines> lines, const std::string& label) {
  tracts_ = std::move(lines);
  ++tractsSerial_;
  const Polylines& l = *tracts_;
  state_.tractPath = label;
  state_.tractCount = l.lineCount();
  state_.tractPoints = l.points.size();
  double total = 0;
  for (std::size_t i = 0; i < l.lineCount(); ++i)
    for (std::uint32_t k = l.offsets[i] + 1; k < l.offsets[i + 1]; ++k)
      total += glm::length(l.points[k] - l.points[k - 1]);
  state_.tractMeanLengthMm = l.lineCount() ? total / static_cast<double>(l.lineCount()) : 0;
  state_.hasAgreement = false; // computed for other tracts
  state_.tractDataNames.clear();
  for (const auto& d : l.perPoint)
    if (d.name != render::kTractDisplayColours) state_.tractDataNames.push_back(d.name);
  for (const auto& d : l.perLine)
    state_.tractDataNames.push_back(d.name);
  state_.tractGroupNames.clear();
  for (const auto& g : l.groups)
    state_.tractGroupNames.push_back(g.name);
  applyTractChoice({}, {}); // names belong to a file: new tracts start in DEC with every streamline
  requestSelection();
}

void ViewerScene::applyTractChoice(const ui::SetTractColour& colour, const ui::SetTractGroups& groups) {
  if (!tracts_) {
    if (!colour.value.empty() || !groups.all) throw UsageError("load or track tracts before colouring them");
    return;
  }
  std::shared_ptr<const Polylines> shown = tracts_;
  TractColouringApplied applied;
  if (!colour.value.empty() || !groups.all) {
    // A copy once per choice (not per frame); the near-surface selection carries the display colours
    // of the kept points.
    Polylines lines = *tracts_;
    TractColouring c;
    c.value = colour.value;
    c.range = colour.range;
    if (!groups.all) {
      if (groups.shown.empty())
        lines = lines.subset(std::vector<std::uint32_t>{});
      else
        c.groups = groups.shown;
    }
    applied = applyTractColouring(lines, c, state_.tractPath);
    shown = std::make_shared<const Polylines>(std::move(lines));
  }
  shownTracts_ = std::move(shown);
  tractColour_ = colour;
  tractGroups_ = groups;
  ++tractsSerial_; // the worker's cached display of every tract is stale
  state_.tractColourBy = colour.value;
  if (applied.coloured) state_.tractColourLo = applied.lo, state_.tractColourHi = applied.hi;
  state_.tractGroupShown.assign(state_.tractGroupNames.size(), groups.all ? 1 : 0);
  if (!groups.all)
    for (std::size_t g = 0; g < state_.tractGroupNames.size(); ++g)
      for (const auto& name : groups.shown)
        if (name == state_.tractGroupNames[g]) state_.tractGroupShown[g] = 1;
  if (applied.coloured) logInfo(applied.summary);
}

void ViewerScene::requestSelection() {
  if (!tracts_) return;
  SelectionJob job;
  job.id = latestSelection_ = nextId_++;
  job.tracts = shownTracts_ ? shownTracts_ : tracts_;
  job.tractsSerial = tractsSerial_;
  if (hasMesh_) job.mesh = mesh_;
  job.nearMm = state_.tractsNearMm;
  state_.tractsSelecting = true;
  tractWorker_.requestSelection(std::move(job));
}

void ViewerScene::onTractResult(TractResult& r) {
  using K = TractResult::Kind;
  if (r.kind == K::Failed) {
    if (r.id == latestSelection_) state_.tractsSelecting = false;
    if (r.id == latestTracking_) {
      state_.tracking = false;
      state_.trackStatus = "failed: " + r.error;
    }
    setError("while " + r.what + ": " + r.error);
    return;
  }
  if (r.kind == K::Selection) {
    if (r.id != latestSelection_) return; // a newer selection is on its way
    state_.tractsSelecting = false;
    if (!tractRenderer_) tractRenderer_ = std::make_unique<render::TractRenderer>();
    if (r.display != uploaded_) {
      tractRenderer_->upload(*r.display);
      uploaded_ = r.display;
    }
    ++displaySerial_;
    tractsSlab_ = r.slab;
    tractsPlane_ = r.plane;
    state_.tractsSlab = r.slab;
    state_.tractsShownLines = tractRenderer_->lineCount();
    state_.tractsShownPoints = tractRenderer_->pointCount();
    logInfo("tracts shown: " + std::to_string(r.lines) + " streamline pieces, " + std::to_string(r.points) +
            " points" + (r.slab ? " (slab around the plane)" : ""));
  } else if (r.kind == K::Tracking) {
    if (r.id != latestTracking_) return;
    state_.tracking = false;
    state_.trackStatus = r.report;
    logInfo(r.report);
    if (!r.cancelled) setTracts(std::move(r.tracts), "tracked in the viewer");
  } else if (r.kind == K::Agreement) {
    if (r.id != latestAgreement_) return;
    const surfaces::AgreementResult& a = r.agreement;
    state_.hasAgreement = true;
    state_.agreementHistogram.assign(a.histogram.begin(), a.histogram.end());
    state_.agreementBinDeg = a.binDeg;
    state_.agreementMeanDeg = a.meanDeg;
    state_.agreementMedianDeg = a.medianDeg;
    state_.agreementFracBelow15 = a.fracBelow15;
    state_.agreementPoints = a.anglesDeg.size();
    state_.agreementNearPoints = a.nearPoints;
    state_.agreementSkipped = a.skippedTangent + a.skippedDegenerate;
    std::string histogram;
    for (std::size_t b = 0; b < a.histogram.size(); ++b)
      histogram += (b ? " " : "") + std::to_string(a.histogram[b]);
    char text[256];
    std::snprintf(text, sizeof text,
                  "agreement: %zu points compared, %zu within %g mm (%zu steep crossings, %zu without an "
                  "in-surface direction), mean %.4f deg, median %.4f deg, below 15 deg %.6f, histogram [",
                  a.anglesDeg.size(), a.nearPoints, state_.agreementNearMm, a.skippedTangent,
                  a.skippedDegenerate, a.meanDeg, a.medianDeg, a.fracBelow15);
    logInfo(text + histogram + "] on the " + state_.agreementSurface);
  } else if (r.kind == K::Saved) {
    state_.saveStatus = "wrote " + r.path;
    logInfo(state_.saveStatus);
  }
}

void ViewerScene::tractFrame(int p, bool fabricChanged, bool moving) {
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
  f.style.widthPx = static_cast<float>(state_.tractWidthPx * outputSize_[p].x / std::max(rect[2], 1));
  TractPick pick;
  if (tractsSlab_) pick.plane = tractsPlane_;
  TractOverlayOptions overlay;
  overlay.nearMm = state_.tractsNearMm;
  overlay.clipMm = state_.tractsClipMm;
  overlay.clipDepthMm = state_.tractsClipOffsetMm;
  const TractClip clip = tractClip(pick, overlay, glm::vec3(camera(p).forward()), meshCentre_);
  f.style.plane = clip.plane;
  f.style.slabMm = clip.slabMm;
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
  state_.tractsLevel = layer.shownLevel();
  const std::size_t all = tractRenderer_->segmentCount(layer.shownLevel());
  state_.tractsLevelFraction =
      all ? static_cast<double>(layer.shownSegments()) / static_cast<double>(all) : 1.0;
}

void ViewerScene::startTracking(const ui::TrackRequest& request) {
  if (!data_) throw UsageError("load a tensor volume before tracking");
  ui::TrackRequest r = request;
  if (r.seeds == ui::SeedKind::Slice && r.sliceIndex < 0)
    r.sliceIndex = state_.slice[static_cast<std::size_t>(std::clamp(r.sliceAxis, 0, 2))];
  surfaces::validate(trackingOptions(r));
  TrackingJob job;
  job.id = nextId_++;
  job.data = data_;
  if (hasMesh_) job.mesh = mesh_;
  job.request = r;
  tractWorker_.requestTracking(std::move(job)); // throws while tracking runs
  latestTracking_ = nextId_ - 1;
  state_.tracking = true;
  state_.trackProgress = 0;
  state_.trackSeedsDone = 0;
  state_.trackStatus = "tracking...";
}

void ViewerScene::startAgreement(const ui::ComputeAgreement& a) {
  if (!(a.nearMm >= 0 && a.nearMm <= 1000)) throw UsageError("agreement distance must lie in [0, 1000] mm");
  if (a.bins < 1 || a.bins > 90) throw UsageError("agreement bins must lie in 1..90");
  if (state_.busy || state_.surfacePending || state_.tractsLoading) {
    pendingAgreement_ = a; // for the surface and tracts on their way, not the ones they replace
    state_.agreementRunning = true;
    return;
  }
  if (!tracts_) throw UsageError("load or track tracts before computing the agreement");
  if (!data_ || !hasMesh_) throw UsageError("the agreement needs a tensor volume and a surface on screen");
  AgreementJob job;
  job.id = latestAgreement_ = nextId_++;
  job.tracts = tracts_;
  job.mesh = mesh_;
  job.data = data_;
  job.options.nearMm = a.nearMm;
  job.options.bins = a.bins;
  state_.agreementNearMm = a.nearMm;
  state_.agreementSurface = state_.surfaceText;
  state_.agreementRunning = true;
  tractWorker_.requestAgreement(std::move(job));
}

void ViewerScene::saveTracts(const ui::SaveTracts& a) {
  if (!tracts_) throw UsageError("no tracts to save");
  if (a.path.empty()) throw UsageError("saving tracts: no path given");
  if (!isTractFileName(a.path)) throw UsageError(a.path + ": tract files end in .tck, .trk or .vtk");
  if (!mayWrite(a.path, a.force, ui::Action(a))) return; // an input, or the overwrite prompt
  SaveJob job;
  job.id = nextId_++;
  job.tracts = tracts_;
  job.path = a.path;
  job.overwrite = a.force;
  if (data_)
    job.reference = data_->loaded.field.grid;
  else if (a.path.size() >= 4 && (a.path.ends_with(".trk") || a.path.ends_with(".TRK")))
    throw UsageError("a .trk file needs a loaded tensor volume for its voxel grid");
  state_.saveStatus = "saving " + a.path;
  tractWorker_.requestSave(std::move(job));
}

void ViewerScene::applyKey(ui::Key key) {
  ui::ActionList actions;
  ui::keyActions(key, state_, actions);
  for (const auto& a : actions)
    apply(a);
}

void ViewerScene::apply(const ui::Action& action) {
  try {
    std::visit(
        [&](const auto& a) {
          using T = std::decay_t<decltype(a)>;
          if constexpr (std::is_same_v<T, ui::LoadFile>) {
            loadFile(a);
          } else if constexpr (std::is_same_v<T, ui::SetSurfaceKind>) {
            if (a.kind == ui::SurfaceKind::Other || a.kind == state_.surface) return;
            state_.surface = a.kind;
            if (a.kind == ui::SurfaceKind::Fibre && otherSpec_.kind != SurfaceSpec::Kind::Fibre)
              state_.surfaceText = "fibre surface: enter a seed line and press Build";
            requestSurface();
          } else if constexpr (std::is_same_v<T, ui::SetSurfaceSpec>) {
            const SurfaceSpec spec = parseSurfaceSpec(a.text);
            addInput(spec.file);
            for (const auto& part : spec.parts)
              addInput(part.file);
            applySpec(spec);
            requestSurface();
          } else if constexpr (std::is_same_v<T, ui::SetFaThreshold>) {
            state_.faThreshold = std::clamp(a.value, 0.01, 0.99);
            state_.surface = ui::SurfaceKind::FaIsosurface;
            requestSurface();
          } else if constexpr (std::is_same_v<T, ui::SetSlice>) {
            const int axis = std::clamp(a.axis, 0, 2);
            state_.slice[axis] = std::clamp(a.index, 0, std::max(state_.sliceCount[axis] - 1, 0));
            state_.surface = sliceKind(axis);
            requestSurface();
          } else if constexpr (std::is_same_v<T, ui::SetFabricParams>) {
            state_.fabric = a.params;
            dataChanged();
          } else if constexpr (std::is_same_v<T, ui::SetView>) {
            setView(a.view);
          } else if constexpr (std::is_same_v<T, ui::SetNeurological>) {
            state_.neurological = a.on;
            using V = render::StandardView;
            if (state_.view == V::Axial || state_.view == V::Coronal || state_.view == V::Sagittal)
              setView(state_.view);
          } else if constexpr (std::is_same_v<T, ui::SetSplit>) {
            if (a.mode && *a.mode != state_.secondPane) {
              state_.secondPane = *a.mode;
              dataChanged();
            }
            if (a.on == state_.split) return;
            state_.split = a.on;
            if (a.on) cameras_[1] = cameras_[0];
            if (data_)
              for (int p = 0; p < 2; ++p)
                cameras_[p].fit(data_->lo, data_->hi, paneAspect(p));
            activePane_ = 0;
            cameraChanged();
          } else if constexpr (std::is_same_v<T, ui::SetLinkedCameras>) {
            state_.linked = a.on;
            cameras_[1] = cameras_[0];
            cameraChanged();
          } else if constexpr (std::is_same_v<T, ui::SetSecondPane>) {
            state_.secondPane = a.mode;
            dataChanged();
          } else if constexpr (std::is_same_v<T, ui::ResetView>) {
            setView(homeView_);
          } else if constexpr (std::is_same_v<T, ui::Rotate>) {
            const auto rect = paneRect(a.pane < 0 ? activePane_ : a.pane);
            const double s = std::max(std::min(rect[2], rect[3]), 1);
            // Arcball from the pane centre in steps of <= 10 pixels, like a real drag.
            const int n =
                std::max(1, static_cast<int>(std::ceil(std::max(std::abs(a.dx), std::abs(a.dy)) / 10.0)));
            render::Camera& cam = cameraFor(a.pane);
            for (int i = 0; i < n; ++i)
              cam.trackball({0.0, 0.0}, {2.0 * a.dx / n / s, -2.0 * a.dy / n / s});
            cameraChanged();
          } else if constexpr (std::is_same_v<T, ui::Pan>) {
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
          } else if constexpr (std::is_same_v<T, ui::Zoom>) {
            if (a.factor > 0) cameraFor(a.pane).zoom(1.0 / a.factor);
            cameraChanged();
          } else if constexpr (std::is_same_v<T, ui::SaveCamera>) {
            if (mayWrite(a.path, a.force, action)) writeCameraFile(a.path, cameraFor(-1));
          } else if constexpr (std::is_same_v<T, ui::ConfirmOverwrite>) {
            // Screenshots are the window's: it answers the prompt itself and takes them.
            if (auto forced = answerOverwrite(a.overwrite);
                forced && !std::holds_alternative<ui::Screenshot>(*forced))
              apply(*forced);
          } else if constexpr (std::is_same_v<T, ui::LoadCamera>) {
            cameraFor(-1) = readCameraFile(a.path);
            if (state_.linked) cameras_[1] = cameras_[0];
            cameraChanged();
          } else if constexpr (std::is_same_v<T, ui::LoadTracts>) {
            if (state_.tractsLoading) throw UsageError("tracts are still loading");
            const std::string path = a.path;
            addInput(path);
            state_.tractsLoading = true;
            tractsLoading_ = std::async(std::launch::async, [path] {
              try {
                return readTracts(path);
              } catch (...) {
                rethrowWithContext("while loading tracts " + path);
              }
            });
            state_.tractPath.clear();
            pendingTractPath_ = path;
          } else if constexpr (std::is_same_v<T, ui::SetTractsVisible>) {
            state_.tractsVisible = a.on;
          } else if constexpr (std::is_same_v<T, ui::SetTractsNear>) {
            if (!(a.mm >= 0 && a.mm <= 1000)) throw UsageError("tract distance must lie in [0, 1000] mm");
            state_.tractsNearMm = a.mm;
            requestSelection();
          } else if constexpr (std::is_same_v<T, ui::SetTractsClip>) {
            if (!(a.mm >= 0 && a.mm <= 1000))
              throw UsageError("clip slab half-width must lie in [0, 1000] mm");
            if (!(std::abs(a.offsetMm) <= 1000))
              throw UsageError("clip slab depth must lie in [-1000, 1000] mm");
            state_.tractsClipMm = a.mm;
            state_.tractsClipOffsetMm = a.offsetMm;
            ++tractStyleSerial_;
          } else if constexpr (std::is_same_v<T, ui::SetTractColour>) {
            applyTractChoice(a, tractGroups_);
            requestSelection();
          } else if constexpr (std::is_same_v<T, ui::SetTractGroups>) {
            applyTractChoice(tractColour_, a);
            requestSelection();
          } else if constexpr (std::is_same_v<T, ui::SetTractWidth>) {
            if (!(a.px > 0 && a.px <= 32)) throw UsageError("tract width must lie in (0, 32] pixels");
            state_.tractWidthPx = a.px;
            ++tractStyleSerial_;
          } else if constexpr (std::is_same_v<T, ui::TrackTracts>) {
            startTracking(a.request);
          } else if constexpr (std::is_same_v<T, ui::CancelTracking>) {
            tractWorker_.cancelTracking();
          } else if constexpr (std::is_same_v<T, ui::SaveTracts>) {
            saveTracts(a);
          } else if constexpr (std::is_same_v<T, ui::ComputeAgreement>) {
            startAgreement(a);
          } else if constexpr (std::is_same_v<T, ui::DismissError>) {
            state_.errorChain.clear();
          }
          // Screenshot and Quit are performed by the window.
        },
        action);
  } catch (...) {
    setError(currentExceptionMessage());
  }
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
