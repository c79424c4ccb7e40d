// SPDX-License-Identifier: GPL-3.0-or-later
#include "ui/session/viewer_session.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/model/tensor.h"
#include "surfaces/analyses/near_surface.h"
#include "surfaces/analyses/tract_profile.h"
#include "surfaces/selection/tract_selection.h"
#include "surfaces/slices.h"
#include "ui/session/region_spec.h"
#include "ui/session/render_job.h"
#include "ui/session/tensor_input.h"
#include "ui/session/track_request.h"
#include "ui/session/tract_colouring.h"
#include "ui/session/tract_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace dtf::session {

namespace {

// 1st, 2nd, 3rd, 4th, ..., 11th, 12th, 13th, ..., 21st.
std::string ordinal(std::size_t n) {
  const std::size_t t = n % 100, u = n % 10;
  const char* suffix = (t >= 11 && t <= 13) ? "th" : u == 1 ? "st" : u == 2 ? "nd" : u == 3 ? "rd" : "th";
  return std::to_string(n) + suffix;
}

constexpr std::size_t kMaxRecent = 8;
constexpr std::size_t kMaxDimmedPoints = 50'000'000;
constexpr int kDrawnPopulations = 3; // the fabric weaves at most the first three fibres of a voxel
const char* const kAxisNames[3] = {"axial", "coronal", "sagittal"};

SurfaceKind sliceKind(int axis) {
  return axis == 0 ? SurfaceKind::Axial : axis == 1 ? SurfaceKind::Coronal : SurfaceKind::Sagittal;
}

render::StandardView homeViewFor(SurfaceKind k) {
  switch (k) {
  case SurfaceKind::Axial:
    return render::StandardView::Axial;
  case SurfaceKind::Coronal:
    return render::StandardView::Coronal;
  case SurfaceKind::Sagittal:
    return render::StandardView::Sagittal;
  default: // curved surfaces: the display convention's axial view, as `dtfabric render --view axial`
    return render::StandardView::Axial;
  }
}

// Whether fibre n of a voxel (strongest first) is woven at `threshold`: among the first three, and at least
// `threshold` times the voxel's strongest.
bool drawn(int n, float amplitude, float strongest, float threshold) {
  return n < kDrawnPopulations && amplitude > 0 && amplitude >= threshold * strongest;
}


} // namespace

ViewerSession::ViewerSession(const std::string& surface) : initialSurface_(surface) {
  if (!surface.empty()) {
    try {
      applySpec(parseSurfaceSpec(surface));
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
}

ViewerSession::~ViewerSession() = default;

void ViewerSession::setError(const std::string& message) {
  state_.errorChain = splitErrorChain(message);
  ++errorSerial_;
}

void ViewerSession::addInput(const std::string& path) {
  if (!path.empty() && std::find(inputs_.begin(), inputs_.end(), path) == inputs_.end())
    inputs_.push_back(path);
}

bool ViewerSession::mayWrite(const std::string& path, bool force, const Action& action) {
  try {
    io::refuseOverwritingInput(path, inputs_);
    if (force || !io::outputExists(path)) return true;
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

std::optional<Action> ViewerSession::answerOverwrite(bool overwrite) {
  std::optional<Action> a;
  a.swap(pendingOverwrite_);
  state_.overwritePath.clear();
  if (!a || !overwrite) return std::nullopt;
  if (auto* shot = std::get_if<Screenshot>(&*a)) shot->force = true;
  if (auto* cam = std::get_if<SaveCamera>(&*a)) cam->force = true;
  if (auto* tracts = std::get_if<SaveTracts>(&*a)) tracts->force = true;
  if (auto* saved = std::get_if<SaveSession>(&*a)) saved->force = true;
  return a;
}

void ViewerSession::addRecent(const std::string& path) {
  auto& r = state_.recent;
  r.erase(std::remove(r.begin(), r.end(), path), r.end());
  r.insert(r.begin(), path);
  if (r.size() > kMaxRecent) r.resize(kMaxRecent);
}

bool ViewerSession::settled() const {
  return !worker_.busy() && !state_.busy && !state_.tractsLoading && !tractWorker_.busy() &&
         !roiWorker_.busy() && !pendingAgreement_;
}

render::FabricParams ViewerSession::fabricOnScreen() const {
  return paramsOnSurface(state_.fabric, state_.surface == SurfaceKind::FaIsosurface); // no allocation
}

SurfaceSpec ViewerSession::currentSpec() const {
  SurfaceSpec s;
  const int axis = sliceAxisOf(state_.surface);
  if (state_.surface == SurfaceKind::FaIsosurface) {
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

void ViewerSession::applySpec(const SurfaceSpec& spec) {
  switch (spec.kind) {
  case SurfaceSpec::Kind::Fa:
    state_.surface = SurfaceKind::FaIsosurface;
    state_.faThreshold = spec.value;
    break;
  case SurfaceSpec::Kind::Slice: {
    const int axis = static_cast<int>(surfaces::parseSliceAxis(spec.axis));
    state_.surface = sliceKind(axis);
    if (spec.index >= 0) state_.slice[axis] = std::min(spec.index, std::max(state_.sliceCount[axis] - 1, 0));
    break;
  }
  case SurfaceSpec::Kind::Fibre: {
    state_.surface = SurfaceKind::Fibre;
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
    state_.surface = SurfaceKind::Other;
    otherSpec_ = spec;
    break;
  }
}

void ViewerSession::replaceField(TensorField field) {
  if (!data_ || data_->fibres || field.grid.dims != data_->loaded.field.grid.dims) return;
  auto d = std::make_shared<ViewerDataset>(*data_);
  d->loaded.field = std::move(field);
  data_ = std::move(d);
  ++fieldSerial_;
  requestSurface();
}

void ViewerSession::requestSurface() {
  if (!data_) return;
  if ((state_.surface == SurfaceKind::Fibre && otherSpec_.kind != SurfaceSpec::Kind::Fibre) ||
      (state_.surface == SurfaceKind::Other && otherSpec_.text.empty()))
    return; // waits for a seed line / spec
  latestSurface_ = nextId_++;
  state_.surfacePending = true;
  worker_.requestSurface(latestSurface_, data_, currentSpec());
}

void ViewerSession::loadFile(const LoadFile& a) {
  const std::string layout = a.layout.empty() ? "auto" : a.layout;
  if (!io::isFibreLayoutName(layout)) io::parseLayout(layout); // a usage error before the worker runs
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
  addInput(io::gradientSibling(a.path, ".bval"));
  addInput(io::gradientSibling(a.path, ".bvec"));
  addInput(a.tensor);
  latestLoad_ = nextId_++;
  latestSurface_ = latestLoad_;
  requested_ = a;
  requested_.layout = layout;
  state_.busy = true;
  state_.busyStage = "reading " + a.path;
  busySince_ = std::chrono::steady_clock::now();
  // A surface the user named for the first load (`view --surface fa=...`) is refused, as `render` refuses it,
  // when a fibre set has no FA; the default one gives way to a slice.
  const bool named = !data_ && !initialSurface_.empty();
  worker_.requestLoad(latestLoad_, a.path, layout, a.tensor, first, !named);
}

void ViewerSession::setMesh(Mesh&& mesh) {
  mesh_ = std::make_shared<const Mesh>(std::move(mesh));
  ++meshSerial_;
  glm::vec3 lo, hi;
  mesh_->bounds(lo, hi);
  meshCentre_ = 0.5f * (lo + hi);
  state_.triangles = mesh_->triangleCount();
  reselectForSurface();
  requestSelection();
}

void ViewerSession::reselectForSurface() {
  nearRule_ = mesh_ && state_.tractsNearMm > 0 && !surfaces::meshPlane(*mesh_);
  if (tracts_ && roi_.active && state_.roiHideOthers && nearRule_ != roiWholeLines_) requestRoi();
}

void ViewerSession::countFibres() {
  FibreInfo& info = state_.fibres;
  info.populations = {0, 0, 0};
  info.threshold = state_.fabric.fibreThreshold;
  if (!data_ || !data_->fibres) return;
  const FibreSet& set = data_->fibres->set;
  const std::size_t k = static_cast<std::size_t>(set.maxFibres);
  for (std::size_t v = 0; v < set.grid.voxelCount(); ++v) {
    const Fibre* f = &set.fibres[v * k];
    int n = 0;
    for (std::size_t i = 0; i < k; ++i)
      n += drawn(static_cast<int>(i), f[i].amplitude, f[0].amplitude, info.threshold) ? 1 : 0;
    if (n > 0) ++info.populations[static_cast<std::size_t>(n - 1)];
  }
}

void ViewerSession::onResult(WorkerResult& r) {
  using K = WorkerResult::Kind;
  if (r.id < latestLoad_) return; // belongs to data already replaced
  if (r.kind == K::Loaded) {
    data_ = r.data;
    loaded_ = requested_;
    const ViewerDataset& d = *data_;
    const TensorField& f = d.loaded.field;
    state_.busy = false;
    state_.hasData = true;
    DataInfo& info = state_.data;
    info.path = d.path;
    info.layout = d.fibres ? io::fibreLayoutName(d.fibres->layout) : io::layoutName(d.loaded.layout);
    info.layoutReason = d.loaded.layoutReason;
    info.orientation = f.grid.orientationCode();
    info.dims = f.grid.dims;
    info.spacing = f.grid.spacing;
    info.validVoxels = static_cast<std::size_t>(std::count(f.valid.begin(), f.valid.end(), 1));
    info.warnings = d.loaded.warnings;
    FibreInfo& fibres = state_.fibres;
    const bool hadFibres = fibres.present;
    fibres = {};
    if (d.fibres) {
      fibres.present = true;
      fibres.path = d.path;
      fibres.layout = io::fibreLayoutName(d.fibres->layout);
      fibres.layoutReason = d.fibres->layoutReason;
      fibres.faSource = d.faSource;
      fibres.slots = d.fibres->set.maxFibres;
      fibres.voxels = d.fibres->set.occupiedVoxels();
      // A fibre set is woven one population per field (the way `dtfabric render` shows it).
      state_.fabric.colour = render::ColourMode::Fibres;
    } else if (hadFibres && state_.fabric.colour == render::ColourMode::Fibres) {
      state_.fabric.colour = render::ColourMode::Medical; // tensors after a fibre set: the default mode again
    }
    countFibres();
    for (int a = 0; a < 3; ++a) {
      state_.sliceCount[a] = surfaces::sliceCount(f.grid, static_cast<surfaces::SliceAxis>(a));
      state_.slice[a] = state_.sliceCount[a] / 2;
    }
    applySpec(r.spec);
    if (r.spec.kind == SurfaceSpec::Kind::Slice && r.spec.index < 0) {
      const int axis = sliceAxisOf(state_.surface);
      state_.slice[axis] = state_.sliceCount[axis] / 2;
    }
    ++fieldSerial_;
    mesh_.reset();
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
    ++loadSerial_;
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

void ViewerSession::update() {
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
      LoadedTracts loaded = tractsLoading_.get();
      setTracts(std::move(loaded.lines), pendingTractPath_, loaded.meanLengthMm);
      tractsFile_ = pendingTractPath_;
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
  RoiResult rr;
  while (roiWorker_.poll(rr)) {
    try {
      onRoiResult(rr);
    } catch (...) {
      setError(currentExceptionMessage());
    }
  }
  if (state_.roiSelecting) roiWorker_.progress(&state_.roiStage);
  if (state_.tracking) tractWorker_.tracking(&state_.trackSeedsDone, &state_.trackProgress);
  if (pendingAgreement_ && !state_.busy && !state_.surfacePending && !state_.tractsLoading) {
    const ComputeAgreement a = *pendingAgreement_;
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

void ViewerSession::clearProbe() {
  state_.probe.onSurface = state_.probe.inData = false;
  state_.probe.fibres.clear();
  state_.probe.text.clear();
}

void ViewerSession::probeAt(const glm::dvec3& world) {
  clearProbe();
  ProbeInfo& out = state_.probe;
  if (!data_) return;
  out.onSurface = true;
  out.world = world;
  const TensorField& f = data_->loaded.field;
  out.voxel = glm::ivec3(glm::round(f.grid.toVoxel(world)));
  if (!f.grid.contains(out.voxel.x, out.voxel.y, out.voxel.z)) return;
  const std::size_t i = f.grid.index(out.voxel.x, out.voxel.y, out.voxel.z);
  out.hasTensor = f.valid[i] && (!data_->fibres || data_->pairedTensor);
  if (out.hasTensor) {
    const EigenSystem e = eigenDecompose(f.tensors[i]);
    out.fa = fractionalAnisotropy(e.values);
    out.eigenvalues = e.values;
    out.e1 = e.vectors[0];
  }
  if (data_->fibres) {
    const FibreSet& set = data_->fibres->set;
    const Fibre* v = set.at(out.voxel.x, out.voxel.y, out.voxel.z);
    const float threshold = state_.fabric.fibreThreshold;
    for (int n = 0; n < set.maxFibres && v[n].amplitude > 0; ++n) {
      ProbeFibre p;
      p.direction = v[n].direction;
      p.amplitude = v[n].amplitude;
      p.relative = v[n].amplitude / v[0].amplitude;
      p.drawn = drawn(n, v[n].amplitude, v[0].amplitude, threshold);
      out.fibres.push_back(p);
    }
  }
  out.inData = out.hasTensor || !out.fibres.empty();
  if (out.inData) out.text = describeProbe(out);
}

std::string describeProbe(const ProbeInfo& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "voxel %d %d %d", p.voxel.x, p.voxel.y, p.voxel.z);
  std::string text = buf;
  if (p.hasTensor) {
    std::snprintf(buf, sizeof buf, ", FA %.4f, e1 %.3f %.3f %.3f, lambda %.2e %.2e %.2e", p.fa, p.e1.x,
                  p.e1.y, p.e1.z, p.eigenvalues.x, p.eigenvalues.y, p.eigenvalues.z);
    text += buf;
  }
  if (!p.fibres.empty()) {
    text += "; fibres:";
    for (std::size_t n = 0; n < p.fibres.size(); ++n) {
      const ProbeFibre& f = p.fibres[n];
      std::snprintf(buf, sizeof buf, "%s (%.3f %.3f %.3f) amplitude %.3g (%.0f%%)%s", n ? "," : "",
                    f.direction.x, f.direction.y, f.direction.z, f.amplitude, 100.0 * f.relative,
                    f.drawn ? "" : " not drawn");
      text += buf;
    }
  } else if (!p.hasTensor) {
    text += ": no fibre";
  }
  return text;
}

double meanLineLengthMm(const Polylines& l) {
  double total = 0;
  for (std::size_t i = 0; i < l.lineCount(); ++i)
    for (std::uint32_t k = l.offsets[i] + 1; k < l.offsets[i + 1]; ++k)
      total += glm::length(l.points[k] - l.points[k - 1]);
  return l.lineCount() ? total / static_cast<double>(l.lineCount()) : 0;
}

void ViewerSession::setTracts(std::shared_ptr<const Polylines> lines, const std::string& label,
                              std::optional<double> meanLengthMm) {
  tracts_ = std::move(lines);
  ++tractsSerial_;
  const Polylines& l = *tracts_;
  state_.tractPath = label;
  state_.tractCount = l.lineCount();
  state_.tractPoints = l.points.size();
  state_.tractMeanLengthMm = meanLengthMm ? *meanLengthMm : meanLineLengthMm(l);
  state_.hasAgreement = false; // computed for other tracts
  state_.tractDataNames.clear();
  for (const auto& d : l.perPoint)
    if (d.name != render::kTractDisplayColours) state_.tractDataNames.push_back(d.name);
  for (const auto& d : l.perLine)
    state_.tractDataNames.push_back(d.name);
  state_.tractGroupNames.clear();
  for (const auto& g : l.groups)
    state_.tractGroupNames.push_back(g.name);
  // The regions stay; until the worker answers for the new tracts (building their index first), every
  // streamline counts as selected.
  roi_.tracts = tracts_;
  roi_.lines.reset();
  roi_.active = false;
  ++roi_.generation;
  ++roiTractsSerial_;
  roiSubset_.reset();
  state_.roiActive = false;
  state_.roiSelected = l.lineCount();
  applyTractChoice({}, {}); // names belong to a file: new tracts start in DEC with every streamline
  requestSelection();
  requestRoi();
}

void ViewerSession::applyTractChoice(const SetTractColour& colour, const SetTractGroups& groups) {
  if (!tracts_) {
    if (!colour.value.empty() || !groups.all) throw UsageError("load or track tracts before colouring them");
    return;
  }
  // The ROI selection first: the streamlines it leaves out are dropped (hidden) or marked to be dimmed
  // once the colouring is done.
  TractChoice c;
  c.roi = roi_.active && roi_.lines && roi_.tracts == tracts_;
  // Dimming copies every point with a colour (28 bytes a point): past kMaxDimmedPoints the others are hidden.
  c.dim = c.roi && !state_.roiHideOthers && tracts_->points.size() <= kMaxDimmedPoints;
  if (c.roi && !state_.roiHideOthers && !c.dim)
    state_.roiStatus = "too many points to dim the streamlines left out: they are hidden";
  c.base = tracts_;
  if (c.roi && !c.dim)
    c.base = roiSubset_ ? roiSubset_ // made off the UI thread
                        : std::make_shared<const Polylines>(render::decimateForDisplay(*tracts_, *roi_.lines));
  c.roiLines = c.roi ? roi_.lines : nullptr;
  // Each point's node along the profiled streamlines (the Profile panel's hover band and the colouring by
  // the profile's value, both drawn by the tract shader from this array).
  c.byProfile = colour.value == kProfileColouring;
  c.nodes = state_.profile.on || c.byProfile;
  c.colouring.value = c.byProfile ? std::string() : colour.value;
  c.colouring.range = colour.range;
  if (!groups.all) {
    if (groups.shown.empty())
      c.noGroups = true;
    else
      c.colouring.groups = groups.shown;
  }
  c.path = state_.tractPath;
  const bool byProfile = c.byProfile;
  checkTractColouring(*c.base, c.colouring, c.path); // a missing name fails here, whichever thread colours
  // Past choiceSyncPoints_ the copy and the colouring run on the tract worker, before the selection that
  // draws them (requestSelection carries the choice until its result comes).
  pendingChoice_.reset();
  TractColouringApplied applied;
  if (c.copies() && c.base->points.size() > choiceSyncPoints_) {
    pendingChoice_ = std::make_shared<const TractChoice>(std::move(c));
  } else {
    ShownTracts shown = prepareShownTracts(c);
    shownTracts_ = std::move(shown.lines);
    applied = shown.applied;
  }
  if (byProfile) {
    // The range is the profile's, known when its result comes (ViewerScene); until then 0..1.
    applied.coloured = true;
    applied.lo = colour.range ? colour.range->first : state_.tractColourLo;
    applied.hi = colour.range ? colour.range->second : state_.tractColourHi;
    applied.summary = "tracts coloured by the profile's value at each point's node";
  }
  tractColour_ = colour;
  tractGroups_ = groups;
  ++tractsSerial_; // the worker's cached display of every tract is stale
  state_.tractColourBy = colour.value;
  state_.tractGroupShown.assign(state_.tractGroupNames.size(), groups.all ? 1 : 0);
  if (!groups.all)
    for (std::size_t g = 0; g < state_.tractGroupNames.size(); ++g)
      for (const auto& name : groups.shown)
        if (name == state_.tractGroupNames[g]) state_.tractGroupShown[g] = 1;
  if (!pendingChoice_ || byProfile) showApplied(applied);
}

void ViewerSession::showApplied(const TractColouringApplied& applied) {
  if (!applied.coloured) return;
  state_.tractColourLo = applied.lo, state_.tractColourHi = applied.hi;
  logInfo(applied.summary);
}

void ViewerSession::requestSelection(std::size_t pointCap) {
  if (!tracts_) return;
  SelectionJob job;
  job.pointCap = pointCap;
  job.id = latestSelection_ = nextId_++;
  job.tracts = shownTracts_ ? shownTracts_ : tracts_;
  job.choice = pendingChoice_; // set: the worker makes the tracts shown first
  job.tractsSerial = tractsSerial_;
  job.mesh = mesh_;
  job.nearMm = state_.tractsNearMm;
  state_.tractsSelecting = true;
  tractWorker_.requestSelection(std::move(job));
}

void ViewerSession::onTractResult(TractResult& r) {
  using K = TractResult::Kind;
  if (r.kind == K::Failed) {
    if (r.id == latestSelection_) {
      state_.tractsSelecting = false;
      pendingChoice_.reset(); // the choice failed: the tracts on screen stay
    }
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
    if (r.shown && pendingChoice_) { // the choice made on the worker: now on screen
      const bool byProfile = pendingChoice_->byProfile;
      pendingChoice_.reset();
      shownTracts_ = r.shown;
      if (!byProfile) showApplied(r.applied);
    }
    // A quick pass that sampled the streamlines is drawn now and followed by the full one, which a newer
    // change cancels.
    if (r.lineStep > 1 && r.pointCap < kNearSurfacePointCap) requestSelection();
    display_ = r.display;
    allDisplay_ = r.allDisplay;
    ++displaySerial_;
    tractsSlab_ = r.slab;
    tractsPlane_ = r.plane;
    state_.tractsSlab = r.slab;
    state_.tractsShownLines = r.display->lines; // after the display decimation
    state_.tractsShownPoints = r.display->points.size();
    logInfo("tracts shown: " + std::to_string(r.lines) + " streamline pieces, " + std::to_string(r.points) +
            " points" + (r.slab ? " (slab around the plane)" : "") +
            (r.lineStep > 1 ? " (near the surface, of every " + ordinal(r.lineStep) + " streamline)" : ""));
  } else if (r.kind == K::Tracking) {
    if (r.id != latestTracking_) return;
    state_.tracking = false;
    state_.trackStatus = r.report;
    logInfo(r.report);
    if (!r.cancelled) {
      setTracts(std::move(r.tracts), "tracked in the viewer");
      tractsFile_.clear();
    }
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

void ViewerSession::startTracking(const TrackRequest& request) {
  if (!data_) throw UsageError("load a tensor volume before tracking");
  if (data_->fibres && !data_->pairedTensor)
    throw UsageError("tracking follows tensors: pair a tensor with the fibre set (--tensor FILE)");
  TrackRequest r = request;
  if (r.seeds == SeedKind::Slice && r.sliceIndex < 0)
    r.sliceIndex = state_.slice[static_cast<std::size_t>(std::clamp(r.sliceAxis, 0, 2))];
  validate(r);
  TrackingJob job;
  job.id = nextId_++;
  job.data = data_;
  job.mesh = mesh_;
  job.request = r;
  tractWorker_.requestTracking(std::move(job)); // throws while tracking runs
  latestTracking_ = nextId_ - 1;
  state_.tracking = true;
  state_.trackProgress = 0;
  state_.trackSeedsDone = 0;
  state_.trackStatus = "tracking...";
}

void ViewerSession::startAgreement(const ComputeAgreement& a) {
  if (!(a.nearMm >= 0 && a.nearMm <= 1000)) throw UsageError("agreement distance must lie in [0, 1000] mm");
  if (a.bins < 1 || a.bins > 90) throw UsageError("agreement bins must lie in 1..90");
  if (state_.busy || state_.surfacePending || state_.tractsLoading) {
    pendingAgreement_ = a; // for the surface and tracts on their way, not the ones they replace
    state_.agreementRunning = true;
    return;
  }
  if (!tracts_) throw UsageError("load or track tracts before computing the agreement");
  if (!data_ || !mesh_) throw UsageError("the agreement needs a tensor volume and a surface on screen");
  if (data_->fibres && !data_->pairedTensor)
    throw UsageError("the agreement measures tracts against tensors: pair a tensor with the fibre set");
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

void ViewerSession::requestRoi() {
  if (!tracts_) return;
  RoiJob job;
  job.id = latestRoi_ = nextId_++;
  job.tracts = tracts_;
  job.tractsSerial = roiTractsSerial_;
  job.set = state_.roiSet;
  job.subset = state_.roiHideOthers;
  job.subsetWholeLines = roiWholeLines_ = nearRule_;
  roi_.pending = true;
  state_.roiSelecting = true;
  roiWorker_.request(std::move(job));
}

void ViewerSession::onRoiResult(RoiResult& r) {
  if (r.id != latestRoi_) return; // a newer selection is on its way
  roi_.pending = false;
  state_.roiSelecting = false;
  if (!r.error.empty()) {
    setError("while selecting streamlines with the regions: " + r.error);
    return;
  }
  const bool redraw = r.active || roi_.active;
  roi_.tracts = tracts_;
  roi_.active = r.active;
  roi_.lines = r.active ? std::move(r.lines) : nullptr;
  roiSubset_ = r.active ? std::move(r.subset) : nullptr;
  ++roi_.generation;
  state_.roiActive = roi_.active;
  state_.roiSelected = roi_.count();
  state_.roiSelectMs = r.selectMs;
  if (r.indexMs > 0)
    logInfo("streamline index built in " + std::to_string(static_cast<long>(r.indexMs)) + " ms");
  if (r.active)
    logInfo("ROI selection: " + std::to_string(state_.roiSelected) + " of " + std::to_string(state_.tractCount) +
            " streamlines");
  if (redraw) {
    applyTractChoice(tractColour_, tractGroups_);
    // Near a curved surface a quick pass first (TractResult::Kind::Selection asks for the full one).
    requestSelection(nearRule_ ? kNearSurfaceQuickPointCap : kNearSurfacePointCap);
  }
}

void ViewerSession::applyRoi(const Action& action) {
  surfaces::RegionSet& set = state_.roiSet;
  std::vector<char>& visible = state_.roiVisible;
  auto at = [&](std::size_t i) {
    if (i >= set.regions.size())
      throw UsageError("no region " + std::to_string(i + 1) + " (the set holds " +
                       std::to_string(set.regions.size()) + ")");
    return i;
  };
  bool reselect = true;
  if (const auto* a = std::get_if<RoiAdd>(&action)) {
    surfaces::Region r = a->spec.empty() ? a->region : parseRegionSpec(a->spec, a->kind);
    r.kind = a->kind;
    surfaces::validate(r);
    if (r.name.empty()) r.name = regionSpecOf(r);
    if (!r.image.empty()) addInput(r.image);
    set.regions.push_back(std::move(r));
    visible.push_back(1);
  } else if (const auto* a = std::get_if<RoiSet>(&action)) {
    surfaces::validate(a->region);
    set.regions[at(a->index)] = a->region;
  } else if (const auto* a = std::get_if<RoiVisible>(&action)) {
    visible[at(a->index)] = a->on ? 1 : 0;
    reselect = false;
  } else if (const auto* a = std::get_if<RoiRemove>(&action)) {
    set.regions.erase(set.regions.begin() + static_cast<std::ptrdiff_t>(at(a->index)));
    visible.erase(visible.begin() + static_cast<std::ptrdiff_t>(a->index));
  } else if (std::holds_alternative<RoiClear>(action)) {
    set.regions.clear();
    visible.clear();
  } else if (const auto* a = std::get_if<RoiEndsOnly>(&action)) {
    set.endsOnly = a->on;
  } else if (const auto* a = std::get_if<RoiHideOthers>(&action)) {
    state_.roiHideOthers = a->on;
    reselect = a->on && roi_.active && !roiSubset_; // the subset is made on the worker
    if (roi_.active && !reselect) {
      applyTractChoice(tractColour_, tractGroups_);
      requestSelection();
    }
  } else if (const auto* a = std::get_if<SaveRegions>(&action)) {
    reselect = false;
    if (a->path.empty()) throw UsageError("saving the regions: no path given");
    if (!mayWrite(a->path, a->force, action)) return;
    writeRegionSetFile(a->path, set);
    state_.roiStatus = "wrote " + a->path;
    logInfo("regions: " + state_.roiStatus);
  } else if (const auto* a = std::get_if<LoadRegions>(&action)) {
    surfaces::RegionSet loaded = readRegionSetFile(a->path); // throws naming the file
    addInput(a->path);
    for (const auto& r : loaded.regions)
      if (!r.image.empty()) addInput(r.image);
    set = std::move(loaded);
    visible.assign(set.regions.size(), 1);
    state_.roiStatus = "read " + a->path;
  }
  if (reselect) requestRoi();
}

void ViewerSession::saveTracts(const SaveTracts& a) {
  if (!tracts_) throw UsageError("no tracts to save");
  if (a.path.empty()) throw UsageError("saving tracts: no path given");
  if (a.selected && !isTractFileName(a.path))
    throw UsageError(a.path + ": tract files end in .tck, .trk, .trx or .vtk");
  auto isTrx = [](std::string p) {
    std::transform(p.begin(), p.end(), p.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return p.ends_with(".trx");
  };
  if (!a.asGroup.empty() && !isTrx(a.path))
    throw UsageError(a.path + ": saving the selection as a group needs a .trx output");
  if (a.selected && roi_.pending)
    throw UsageError("the selection is still being computed (wait for it before saving it)");
  if (!a.selected && !isTractFileName(a.path)) throw UsageError(a.path + ": tract files end in .tck, .trk or .vtk");
  if (!mayWrite(a.path, a.force, Action(a))) return; // an input, or the overwrite prompt
  SaveJob job;
  job.id = nextId_++;
  job.tracts = tracts_;
  job.path = a.path;
  job.overwrite = a.force;
  if (a.selected) {
    job.keep = roi_.active && roi_.lines ? roi_.lines : nullptr;
    if (!job.keep) { // no region: every streamline is selected
      auto all = std::make_shared<std::vector<std::uint32_t>>(tracts_->lineCount());
      for (std::uint32_t i = 0; i < all->size(); ++i)
        (*all)[i] = i;
      job.keep = std::move(all);
    }
    job.asGroup = a.asGroup;
  }
  if (data_)
    job.reference = data_->loaded.field.grid;
  else if (a.path.size() >= 4 && (a.path.ends_with(".trk") || a.path.ends_with(".TRK")))
    throw UsageError("a .trk file needs a loaded tensor volume for its voxel grid");
  else if (isTrx(a.path))
    throw UsageError(a.path + ": a .trx file needs a loaded tensor volume for its reference grid");
  state_.saveStatus = "saving " + a.path;
  tractWorker_.requestSave(std::move(job));
}

void ViewerSession::apply(const Action& action) {
  try {
    std::visit(
        [&](const auto& a) {
          using T = std::decay_t<decltype(a)>;
          if constexpr (std::is_same_v<T, LoadFile>) {
            loadFile(a);
          } else if constexpr (std::is_same_v<T, SetSurfaceKind>) {
            if (a.kind == SurfaceKind::Other || a.kind == state_.surface) return;
            state_.surface = a.kind;
            if (a.kind == SurfaceKind::Fibre && otherSpec_.kind != SurfaceSpec::Kind::Fibre)
              state_.surfaceText = "fibre surface: enter a seed line and press Build";
            requestSurface();
          } else if constexpr (std::is_same_v<T, SetSurfaceSpec>) {
            const SurfaceSpec spec = parseSurfaceSpec(a.text);
            addInput(spec.file);
            for (const auto& part : spec.parts)
              addInput(part.file);
            applySpec(spec);
            requestSurface();
          } else if constexpr (std::is_same_v<T, SetFaThreshold>) {
            state_.faThreshold = std::clamp(a.value, 0.01, 0.99);
            state_.surface = SurfaceKind::FaIsosurface;
            requestSurface();
          } else if constexpr (std::is_same_v<T, SetSlice>) {
            const int axis = std::clamp(a.axis, 0, 2);
            state_.slice[axis] = std::clamp(a.index, 0, std::max(state_.sliceCount[axis] - 1, 0));
            state_.surface = sliceKind(axis);
            requestSurface();
          } else if constexpr (std::is_same_v<T, SetFabricParams>) {
            render::FabricParams p = a.params;
            if (state_.fibres.present && p.colour != render::ColourMode::Fibres)
              throw UsageError(
                  "a fibre set is shown in the fibres colour mode (medical and engineering colour "
                  "a tensor's eigenvectors)");
            const bool recount = p.fibreThreshold != state_.fabric.fibreThreshold;
            state_.fabric = p;
            if (recount) countFibres();
          } else if constexpr (std::is_same_v<T, LoadTracts>) {
            if (state_.tractsLoading) throw UsageError("tracts are still loading");
            const std::string path = a.path;
            addInput(path);
            state_.tractsLoading = true;
            tractsLoading_ = std::async(std::launch::async, [path] {
              try {
                // The whole set's statistics here too: a whole-brain tractogram holds 100 M+ points.
                LoadedTracts loaded;
                auto lines = std::make_shared<const Polylines>(readTracts(path));
                loaded.meanLengthMm = meanLineLengthMm(*lines);
                loaded.lines = std::move(lines);
                return loaded;
              } catch (...) {
                rethrowWithContext("while loading tracts " + path);
              }
            });
            state_.tractPath.clear();
            pendingTractPath_ = path;
          } else if constexpr (std::is_same_v<T, SetTractsVisible>) {
            state_.tractsVisible = a.on;
          } else if constexpr (std::is_same_v<T, SetTractsNear>) {
            if (!(a.mm >= 0 && a.mm <= 1000)) throw UsageError("tract distance must lie in [0, 1000] mm");
            state_.tractsNearMm = a.mm;
            reselectForSurface();
            requestSelection();
          } else if constexpr (std::is_same_v<T, SetTractsClip>) {
            if (!(a.mm >= 0 && a.mm <= 1000))
              throw UsageError("clip slab half-width must lie in [0, 1000] mm");
            if (!(std::abs(a.offsetMm) <= 1000))
              throw UsageError("clip slab depth must lie in [-1000, 1000] mm");
            state_.tractsClipMm = a.mm;
            state_.tractsClipOffsetMm = a.offsetMm;
            ++tractStyleSerial_;
          } else if constexpr (std::is_same_v<T, SetTractColour>) {
            applyTractChoice(a, tractGroups_);
            requestSelection();
          } else if constexpr (std::is_same_v<T, SetTractGroups>) {
            applyTractChoice(tractColour_, a);
            requestSelection();
          } else if constexpr (std::is_same_v<T, SetTractWidth>) {
            if (!(a.px > 0 && a.px <= 32)) throw UsageError("tract width must lie in (0, 32] pixels");
            state_.tractWidthPx = a.px;
            ++tractStyleSerial_;
          } else if constexpr (std::is_same_v<T, TrackTracts>) {
            startTracking(a.request);
          } else if constexpr (std::is_same_v<T, CancelTracking>) {
            tractWorker_.cancelTracking();
          } else if constexpr (std::is_same_v<T, SaveTracts>) {
            saveTracts(a);
          } else if constexpr (std::is_same_v<T, RoiAdd> || std::is_same_v<T, RoiSet> ||
                               std::is_same_v<T, RoiVisible> || std::is_same_v<T, RoiRemove> ||
                               std::is_same_v<T, RoiClear> || std::is_same_v<T, RoiEndsOnly> ||
                               std::is_same_v<T, RoiHideOthers> || std::is_same_v<T, SaveRegions> ||
                               std::is_same_v<T, LoadRegions>) {
            applyRoi(action);
          } else if constexpr (std::is_same_v<T, ComputeAgreement>) {
            startAgreement(a);
          } else if constexpr (std::is_same_v<T, ShowHelp>) {
            state_.helpShown = a.on ? *a.on : !state_.helpShown;
          } else if constexpr (std::is_same_v<T, DismissError>) {
            state_.errorChain.clear();
          }
          // The rest (cameras, panes, screenshots, camera files, the overwrite answer, quit) is the front
          // end's.
        },
        action);
  } catch (...) {
    setError(currentExceptionMessage());
  }
}

} // namespace dtf::session
