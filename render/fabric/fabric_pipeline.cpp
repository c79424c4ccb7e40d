// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric/fabric_pipeline.h"

#include "io/model/error.h"
#include "render/fray.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace dtf::render {

namespace {
// Parameters whose change invalidates the advection state.
auto stateKey(const FabricParams& p) {
  return std::make_tuple(p.lod, p.autoLodPixels, p.spotScale, p.seed, p.noiseSize, p.stepPixels, p.silhouette,
                         p.silhouettePixels, p.noiseBlend, p.guard, p.colour, p.faFloor, p.fibreThreshold, p.fray,
                         p.frayCells);
}

void boundsOf(const Grid& g, glm::vec3& lo, glm::vec3& hi) {
  glm::dvec3 l, h;
  g.worldBounds(l, h);
  lo = glm::vec3(l);
  hi = glm::vec3(h);
}
} // namespace

FabricPipeline::FabricPipeline() {
  for (auto& q : timers_)
    q = createQuery(GL_TIME_ELAPSED);
}

void FabricPipeline::setField(const TensorField& field) {
  field_.upload(field);
  haveField_ = field.grid.voxelCount() > 0;
  if (haveField_) boundsOf(field.grid, fieldLo_, fieldHi_);
  dataChanged_ = true;
}

void FabricPipeline::setFibres(const FibreSet& fibres, const ScalarVolume* fa) {
  fibreSet_ = fibres;
  fibreFa_ = fa ? std::optional<ScalarVolume>(*fa) : std::nullopt;
  fibres_.upload(fibreSet_, fibreFa_ ? &*fibreFa_ : nullptr, uploadedThreshold_);
  haveFibres_ = fibres.grid.voxelCount() > 0;
  if (haveFibres_) boundsOf(fibres.grid, fibreLo_, fibreHi_);
  dataChanged_ = true;
  if (cone_ && cone_->components > 1) uploadUncertainty();
}

void FabricPipeline::clearFibres() {
  fibres_.clear();
  fibreSet_ = FibreSet{};
  fibreFa_.reset();
  haveFibres_ = false;
  dataChanged_ = true;
  if (cone_ && cone_->components > 1) uploadUncertainty();
}

void FabricPipeline::setUncertainty(const ScalarVolume* cone) {
  cone_ = cone ? std::optional<ScalarVolume>(*cone) : std::nullopt;
  uploadUncertainty();
}

void FabricPipeline::uploadUncertainty() {
  dataChanged_ = true;
  if (!cone_) {
    uncertainty_.clear();
    return;
  }
  // Per-fibre cones follow their fibres into the slots the renderer advects (continuousSlots reorders and
  // flips lobes per voxel: each slot's lobe is matched back to the set's fibre by amplitude and |cos|).
  if (cone_->components > 1 && haveFibres_ && fibreSet_.grid.dims == cone_->grid.dims) {
    const FibreSet slotted = continuousSlots(fibreSet_, uploadedThreshold_);
    uncertainty_.upload(slotCones(fibreSet_, slotted, *cone_), 0.0f, 90.0f, 3);
    return;
  }
  uncertainty_.upload(*cone_, 0.0f, 90.0f, 3);
}

void FabricPipeline::setAlong(const ScalarVolume* weight) {
  if (weight && weight->grid.voxelCount() > 0)
    along_.upload(*weight, 0.0f, 1.0f);
  else
    along_.clear();
  dataChanged_ = true;
}

void FabricPipeline::setBackground(const ScalarVolume* volume, float lo, float hi) {
  if (volume)
    background_.upload(*volume, lo, hi);
  else
    background_.clear();
  dataChanged_ = true;
}

bool FabricPipeline::dataBounds(glm::vec3& lo, glm::vec3& hi) const {
  if (haveField_) {
    lo = fieldLo_;
    hi = fieldHi_;
  } else if (haveFibres_) {
    lo = fibreLo_;
    hi = fibreHi_;
  }
  return haveField_ || haveFibres_;
}

glm::vec3 FabricPipeline::noiseOrigin(const FabricParams& p, const glm::vec3& fallback) const {
  if (p.colour == ColourMode::Fibres && haveFibres_) return fibreLo_;
  if (haveField_) return fieldLo_;
  if (haveFibres_) return fibreLo_;
  return fallback;
}

double FabricPipeline::effectiveLod(const FrameView& view, const FabricParams& p) const {
  return p.lod > 0 ? p.lod : p.autoLodPixels * view.pixelMm;
}

int FabricPipeline::fields(const FabricParams& p) const {
  return p.colour == ColourMode::Fibres && fibres_.lobes() >= 3 ? 3 : 2;
}

void FabricPipeline::beginTimer(Pass pass) {
  if (!timing_) return;
  glBeginQuery(GL_TIME_ELAPSED, timers_[pass].id());
  timerUsed_[pass] = true;
}

void FabricPipeline::endTimer() {
  if (timing_) glEndQuery(GL_TIME_ELAPSED);
}

bool FabricPipeline::projectionCurrent(const FrameView& view, const FabricParams& p) const {
  return projected_ && !dataChanged_ && view.viewProj == lastViewProj_ && view.target == lastTarget_ &&
         view.pixelMm == lastPixelMm_ && view.depthRange == lastDepthRange_ && stateKey(p) == stateKey(lastParams_);
}

bool FabricPipeline::project(const FrameView& view, const FabricParams& p, const glm::vec3& noiseFallback,
                             bool forceRestart) {
  NoiseOptions no;
  no.size = p.noiseSize;
  no.spotScale = p.spotScale;
  no.seed = p.seed;
  if (!noiseTile_ || noiseTile_->size != no.size || stateKey(p) != stateKey(lastParams_)) {
    auto tile = cachedReactionDiffusion(no);
    if (tile != noiseTile_) {
      noiseTile_ = tile;
      noise_ = uploadNoise(*tile);
    }
  }
  const bool restart =
      forceRestart || dataChanged_ || view.viewProj != lastViewProj_ || stateKey(p) != stateKey(lastParams_);

  ProjectionSettings ps;
  ps.lod = static_cast<float>(effectiveLod(view, p));
  ps.noiseOrigin = noiseOrigin(p, noiseFallback);
  ps.noiseBlend = static_cast<float>(p.noiseBlend);
  ps.principal = p.colour == ColourMode::Medical;
  ps.faFloor = p.faFloor;
  ps.fibres = p.colour == ColourMode::Fibres;
  ps.uncertainty = &uncertainty_;
  ps.along = &along_;
  ps.fray = static_cast<float>(p.fray);
  ps.frayCells = static_cast<float>(p.frayCells);
  if (ps.fibres && fibres_.empty()) throw GlError("the fibre colour mode needs a fibre set (setFibres)");
  if (ps.fibres && p.fibreThreshold != uploadedThreshold_) { // the threshold is applied on upload
    uploadedThreshold_ = p.fibreThreshold;
    fibres_.upload(fibreSet_, fibreFa_ ? &*fibreFa_ : nullptr, uploadedThreshold_);
    if (cone_ && cone_->components > 1) uploadUncertainty();
  }
  projection_.runTensor(field_, noise_, view, ps, &background_, &fibres_);
  endTimer(); // the projection's timer runs from the caller's geometry stage to here

  const float background = view.depthRange.y + (view.depthRange.y - view.depthRange.x) + 1.0f;
  // Without silhouettes the pass still marks the background, which the advection must not sample.
  const float threshold = p.silhouette ? static_cast<float>(p.silhouettePixels) * view.pixelMm : 3.0e38f;
  const bool reproject = restart && reprojectNext_ && !forceRestart && historyView_ &&
                         historyView_->target == view.target && stateKey(p) == stateKey(lastParams_) &&
                         fields(p) == 2 && advection_.hasHistory();
  reprojectNext_ = false;
  advection_.setCover(view.targetCoverRect);
  beginTimer(kSilhouette);
  if (restart && !reproject) { // the restart from beta finds the silhouettes in the same pass
    silhouette_.resize(projection_.size());
    advection_.resetFindingSilhouettes(projection_.surface(), silhouette_.edges(), threshold, background, fields(p),
                                       p.colour == ColourMode::Fibres);
  } else {
    silhouette_.run(projection_.surface(), threshold, background, &projection_.depth());
  }
  endTimer();
  if (reproject) {
    const FrameView& h = *historyView_;
    // Window coordinates (pixels, depth in [0, 1]) <-> clip coordinates of the guarded target.
    const auto toWindow = [](glm::ivec2 t) {
      glm::mat4 m(1.0f);
      m[0][0] = 0.5f * float(t.x);
      m[1][1] = 0.5f * float(t.y);
      m[2][2] = 0.5f;
      m[3] = glm::vec4(0.5f * float(t.x), 0.5f * float(t.y), 0.5f, 1.0f);
      return m;
    };
    const glm::mat4 windowToWorld = glm::inverse(toWindow(view.target) * view.viewProj);
    const glm::mat4 worldToPrevWindow = toWindow(h.target) * h.viewProj;
    // Another surface: more than a few pixels or 1 mm apart in depth.
    const float tol = std::max(1.0f, 4.0f * std::max(view.pixelMm, h.pixelMm));
    advection_.reproject(projection_.surface(), silhouette_.edges(), projection_.depth(), windowToWorld,
                         worldToPrevWindow, h.view, tol,
                         p.colour == ColourMode::Fibres);
  }
  dataChanged_ = false;
  projected_ = true;
  ++projections_;
  restarted_ = restart;
  if (restart) sinceRestart_ = 0;
  lastViewProj_ = view.viewProj;
  lastTarget_ = view.target;
  lastPixelMm_ = view.pixelMm;
  lastDepthRange_ = view.depthRange;
  lastParams_ = p;
  return restart;
}

void FabricPipeline::keepHistory(const FrameView& view) {
  advection_.keepHistory(projection_.surface());
  historyView_ = view;
}

AdvectionSettings FabricPipeline::advectionSettings(const FabricParams& p) const {
  return {static_cast<float>(p.k), static_cast<float>(p.stepPixels), static_cast<float>(p.epsilon),
          p.colour == ColourMode::Fibres};
}

bool FabricPipeline::countsThisFrame(const FabricParams& p) const {
  // Counting costs an atomic increment per changed pixel (most of them in the first iterations after a
  // restart), and a still cannot stop before the start image has faded (FabricParams::stillMinIterations):
  // only frames that continue their state and reach that many iterations count.
  return !restarted_ && sinceRestart_ + p.iterations >= p.stillMinIterations();
}

void FabricPipeline::advect(const FabricParams& p) {
  const AdvectionSettings as = advectionSettings(p);
  beginTimer(kAdvection);
  const bool count = countsThisFrame(p);
  const int n = fields(p);
  advection_.iterate(n == 3 ? projection_.vectors3() : projection_.vectors(), as, p.iterations, count,
                     &projection_.depth(), n);
  sinceRestart_ += p.iterations;
  restarted_ = false;
  endTimer();
}

bool FabricPipeline::fusesComposite(const FrameView& view, const FabricParams& p) const {
  return !advection_.compute() && view.internal == view.viewport && p.iterations >= 1 && p.sharpen <= 0.0 &&
         projection_.depth().width() == view.target.x && projection_.depth().height() == view.target.y;
}

void FabricPipeline::advectComposing(const FrameView& view, const FabricParams& p, const Texture& colour) {
  if (!fusesComposite(view, p)) throw GlError("FabricPipeline: this frame cannot fuse its composite");
  const AdvectionSettings as = advectionSettings(p);
  const bool count = countsThisFrame(p);
  const int n = fields(p);
  const Texture& vectors = n == 3 ? projection_.vectors3() : projection_.vectors();
  beginTimer(kAdvection);
  advection_.iterate(vectors, as, p.iterations - 1, false, &projection_.depth(), n);
  endTimer();
  sinceRestart_ += p.iterations;
  restarted_ = false;
  beginTimer(kComposite);
  const ShaderProgram& program = composite_.advecting(
      compositeInputs(p), view, compositeSettings(p, glm::ivec2(0), CompositeDepth::Present, true), as, count, n);
  advection_.iterateDrawing(program, vectors, count, projection_.depth(), n, colour);
  endTimer();
}

int FabricPipeline::converge(const FabricParams& p) {
  const AdvectionSettings as = advectionSettings(p);
  const unsigned covered = projection_.coveredPixels();
  // At least as many iterations as it takes the start image's weight (1 - k)^n to fall below epsilon,
  // then until (almost) no pixel changes by more than epsilon per iteration.
  const int minIterations = p.stillMinIterations();
  const int chunk = std::max(p.iterations, 1);
  const bool three = fields(p) == 3;
  restarted_ = false; // converged below: the next frame's count is meaningful
  int done = 0;
  while (done < p.stillMaxIterations) {
    int n = std::min(chunk, p.stillMaxIterations - done);
    bool check = done + n >= minIterations;
    advection_.iterate(three ? projection_.vectors3() : projection_.vectors(), as, n, check,
                       &projection_.depth(), three ? 3 : 2);
    done += n;
    if (check && advection_.changedPixels() <= p.stillChangedFraction * covered) break;
  }
  sinceRestart_ += done;
  return done;
}

CompositeSettings FabricPipeline::compositeSettings(const FabricParams& p, glm::ivec2 origin, CompositeDepth depth,
                                                    bool overBackground) const {
  CompositeSettings cs;
  cs.mode = p.colour;
  cs.r = static_cast<float>(p.r);
  cs.contrast = static_cast<float>(p.contrast);
  cs.lighting = p.lighting;
  cs.silhouettes = p.silhouette;
  cs.depthColour = static_cast<float>(p.depthColour);
  cs.sharpen = static_cast<float>(p.sharpen);
  cs.fadeOutOfPlane = p.fadeOutOfPlane;
  cs.background = !background_.empty();
  cs.anatomy = p.look == Look::Anatomy;
  cs.decFa = p.look == Look::DecFa;
  cs.opacityFa = {p.opacityFaLow, p.opacityFaHigh};
  cs.origin = origin;
  cs.depth = depth;
  cs.overClear = overBackground;
  cs.clearColour = glm::clamp(p.background, 0.0f, 1.0f); // as the RGBA8 output holds it
  return cs;
}

CompositeInputs FabricPipeline::compositeInputs(const FabricParams& p) const {
  CompositeInputs in{&advection_.field(0), &advection_.field(1), &projection_.surface(), &projection_.eigen(),
                     &projection_.lambda()};
  if (p.colour == ColourMode::Fibres) {
    in.p3 = &advection_.field(2);
    in.fibres = &projection_.fibres();
  }
  in.depth = &projection_.depth();
  in.light = &projection_.light();
  return in;
}

void FabricPipeline::composite(const FrameView& view, const FabricParams& p, glm::ivec2 origin,
                               CompositeDepth depth, bool overBackground) {
  const CompositeSettings cs = compositeSettings(p, origin, depth, overBackground);
  const CompositeInputs in = compositeInputs(p);
  beginTimer(kComposite);
  composite_.run(in, view, cs);
  endTimer();
}

void FabricPipeline::compositeDepth(const FrameView& view) {
  composite_.runDepth({nullptr, nullptr, &projection_.surface(), nullptr, &projection_.lambda()}, view,
                      !background_.empty());
}

PassTimes FabricPipeline::lastTimes() const {
  PassTimes t;
  double* out[kPasses] = {&t.projection, &t.silhouette, &t.advection, &t.composite, &t.phong};
  for (int i = 0; i < kPasses; ++i) {
    if (!timerUsed_[i]) continue;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timers_[i].id(), GL_QUERY_RESULT, &ns);
    *out[i] = static_cast<double>(ns) * 1e-6;
  }
  return t;
}

} // namespace dtf::render
