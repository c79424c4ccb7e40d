#include "render/fabric_renderer.h"

#include "render/gl_state.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>

namespace dtf::render {

namespace {
enum Pass { kProjection = 0, kSilhouette, kAdvection, kComposite, kPhong };

// Parameters whose change invalidates the advection state.
auto stateKey(const FabricParams& p) {
  return std::make_tuple(p.lod, p.autoLodPixels, p.spotScale, p.seed, p.noiseSize, p.stepPixels, p.silhouette,
                         p.silhouettePixels, p.noiseBlend, p.guard, p.colour, p.faFloor, p.fibreThreshold);
}
} // namespace

FabricRenderer::FabricRenderer() {
  for (auto& q : timers_) q = createQuery(GL_TIME_ELAPSED);
}

FabricRenderer::~FabricRenderer() = default;

void FabricRenderer::setMesh(const Mesh& mesh) {
  mesh_.upload(mesh);
  dataChanged_ = true;
}

void FabricRenderer::setField(const TensorField& field) {
  field_.upload(field);
  dataChanged_ = true;
}

void FabricRenderer::setFibres(const FibreSet& fibres, const ScalarVolume* fa) {
  fibreSet_ = fibres;
  fibreFa_ = fa ? std::optional<ScalarVolume>(*fa) : std::nullopt;
  fibres_.upload(fibreSet_, fibreFa_ ? &*fibreFa_ : nullptr, uploadedThreshold_);
  dataChanged_ = true;
}

void FabricRenderer::clearFibres() {
  fibres_.clear();
  fibreSet_ = FibreSet{};
  fibreFa_.reset();
  dataChanged_ = true;
}

void FabricRenderer::setBackground(const ScalarVolume* volume, float lo, float hi) {
  if (volume) background_.upload(*volume, lo, hi);
  else background_.clear();
  dataChanged_ = true;
}

void FabricRenderer::resize(int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw GlError("render size " + std::to_string(width) + "x" + std::to_string(height) + " out of range");
  if (glm::ivec2(width, height) == size_) return;
  size_ = {width, height};
  outColour_ = Texture::create2D(GL_RGBA8, width, height);
  outDepth_ = Texture::create2D(GL_DEPTH_COMPONENT32F, width, height);
  output_ = createFramebuffer();
  attachTargets(output_, {&outColour_}, &outDepth_);
  dataChanged_ = true;
}

double FabricRenderer::effectiveLod(const FrameView& view, const FabricParams& p) const {
  return p.lod > 0 ? p.lod : p.autoLodPixels * view.pixelMm;
}

int FabricRenderer::fields(const FabricParams& p) const {
  return p.colour == ColourMode::Fibres && fibres_.lobes() >= 3 ? 3 : 2;
}

void FabricRenderer::beginTimer(int pass) {
  if (!timing_) return;
  glBeginQuery(GL_TIME_ELAPSED, timers_[pass].id());
  timerUsed_[pass] = true;
}

void FabricRenderer::endTimer() {
  if (timing_) glEndQuery(GL_TIME_ELAPSED);
}

void FabricRenderer::prepare(const Camera& camera, const FabricParams& p, bool& restart) {
  if (size_.x < 1) throw GlError("FabricRenderer: resize() before rendering");
  timerUsed_.fill(false);
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
  view_ = FrameView::make(camera, size_, std::max(p.guard, 0), mesh_.boundsLo(), mesh_.boundsHi());
  const bool moving = view_.viewProjViewport != lastCameraViewProj_;
  lastCameraViewProj_ = view_.viewProjViewport;
  if (moving && !still_ && p.movingScale < 1.0)
    view_ = FrameView::make(camera, size_, std::max(p.guard, 0), mesh_.boundsLo(), mesh_.boundsHi(),
                            static_cast<float>(p.movingScale));
  restart = dataChanged_ || view_.viewProj != lastViewProj_ || stateKey(p) != stateKey(lastParams_);

  ProjectionSettings ps;
  ps.lod = static_cast<float>(effectiveLod(view_, p));
  ps.noiseOrigin = mesh_.boundsLo();
  ps.noiseBlend = static_cast<float>(p.noiseBlend);
  ps.principal = p.colour == ColourMode::Medical;
  ps.faFloor = p.faFloor;
  ps.fibres = p.colour == ColourMode::Fibres;
  if (ps.fibres && fibres_.empty()) throw GlError("the fibre colour mode needs a fibre set (setFibres)");
  if (ps.fibres && p.fibreThreshold != uploadedThreshold_) { // the threshold is applied on upload
    uploadedThreshold_ = p.fibreThreshold;
    fibres_.upload(fibreSet_, fibreFa_ ? &*fibreFa_ : nullptr, uploadedThreshold_);
  }
  beginTimer(kProjection);
  projection_.run(mesh_, field_, noise_, view_, ps, &background_, &fibres_);
  endTimer();

  beginTimer(kSilhouette);
  const float background = view_.depthRange.y + (view_.depthRange.y - view_.depthRange.x) + 1.0f;
  // Without silhouettes the pass still marks the background, which the advection must not sample.
  const float threshold = p.silhouette ? static_cast<float>(p.silhouettePixels) * view_.pixelMm : 3.0e38f;
  silhouette_.run(projection_.surface(), threshold, background, &projection_.depth());
  endTimer();

  if (restart)
    advection_.reset(projection_.surface(), silhouette_.edges(), fields(p), p.colour == ColourMode::Fibres);
  dataChanged_ = false;
  lastViewProj_ = view_.viewProj;
  lastParams_ = p;
}

void FabricRenderer::composite(const FabricParams& p) {
  glBindFramebuffer(GL_FRAMEBUFFER, output_.id());
  const float bg[4] = {p.background.x, p.background.y, p.background.z, 1.0f};
  glClearNamedFramebufferfv(output_.id(), GL_COLOR, 0, bg);
  const float one = 1.0f;
  glClearNamedFramebufferfv(output_.id(), GL_DEPTH, 0, &one);
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
  CompositeInputs in{&advection_.field(0), &advection_.field(1), &projection_.surface(), &silhouette_.edges(),
                     &projection_.eigen(),   &projection_.lambda()};
  if (p.colour == ColourMode::Fibres) {
    in.p3 = &advection_.field(2);
    in.fibres = &projection_.fibres();
  }
  beginTimer(kComposite);
  composite_.run(in, view_, cs);
  endTimer();
}

void FabricRenderer::renderFrame(const Camera& camera, const FabricParams& p) {
  const GlStateGuard guard;
  bool restart = false;
  prepare(camera, p, restart);
  AdvectionSettings as{static_cast<float>(p.k), static_cast<float>(p.stepPixels), static_cast<float>(p.epsilon),
                       p.colour == ColourMode::Fibres};
  beginTimer(kAdvection);
  advection_.iterate(projection_.vectors(), as, p.iterations, true, &projection_.depth(), fields(p));
  endTimer();
  composite(p);
}

Image FabricRenderer::renderStill(const Camera& camera, const FabricParams& p) {
  const GlStateGuard guard;
  bool restart = false;
  dataChanged_ = true; // a still always starts from beta: same arguments, same image
  still_ = true;
  prepare(camera, p, restart);
  still_ = false;
  AdvectionSettings as{static_cast<float>(p.k), static_cast<float>(p.stepPixels), static_cast<float>(p.epsilon),
                       p.colour == ColourMode::Fibres};
  const unsigned covered = coveredPixels();
  // At least as many iterations as it takes the start image's weight (1 - k)^n to fall below epsilon,
  // then until (almost) no pixel changes by more than epsilon per iteration.
  int minIterations = p.stillMaxIterations;
  if (p.k > 0 && p.k < 1 && p.epsilon > 0 && p.epsilon < 1)
    minIterations = static_cast<int>(std::ceil(std::log(p.epsilon) / std::log(1.0 - p.k)));
  else if (p.k >= 1)
    minIterations = 1;
  minIterations = std::clamp(minIterations, 1, std::max(p.stillMaxIterations, 1));
  const int chunk = std::max(p.iterations, 1);
  int done = 0;
  while (done < p.stillMaxIterations) {
    int n = std::min(chunk, p.stillMaxIterations - done);
    bool check = done + n >= minIterations;
    advection_.iterate(projection_.vectors(), as, n, check, &projection_.depth(), fields(p));
    done += n;
    if (check && advection_.changedPixels() <= p.stillChangedFraction * covered) break;
  }
  lastIterations_ = done;
  composite(p);
  return readback();
}

void FabricRenderer::renderPhong(const Camera& camera, const glm::vec3& colour) {
  const GlStateGuard guard;
  if (size_.x < 1) throw GlError("FabricRenderer: resize() before rendering");
  timerUsed_.fill(false);
  view_ = FrameView::make(camera, size_, 0, mesh_.boundsLo(), mesh_.boundsHi());
  glBindFramebuffer(GL_FRAMEBUFFER, output_.id());
  const float bg[4] = {0, 0, 0, 1};
  glClearNamedFramebufferfv(output_.id(), GL_COLOR, 0, bg);
  const float one = 1.0f;
  glClearNamedFramebufferfv(output_.id(), GL_DEPTH, 0, &one);
  beginTimer(kPhong);
  phong_.run(mesh_, view_, colour);
  endTimer();
  dataChanged_ = true; // the fabric targets were not updated for this camera
}

Image FabricRenderer::readback() const {
  const GlStateGuard guard;
  Image img(size_.x, size_.y);
  std::vector<std::uint8_t> rows(img.rgba.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(outColour_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rows.size()), rows.data());
  const std::size_t stride = static_cast<std::size_t>(size_.x) * 4;
  for (int y = 0; y < size_.y; ++y)
    std::memcpy(&img.rgba[static_cast<std::size_t>(y) * stride],
                &rows[static_cast<std::size_t>(size_.y - 1 - y) * stride], stride);
  return img;
}

PassTimes FabricRenderer::lastTimes() const {
  PassTimes t;
  double* out[5] = {&t.projection, &t.silhouette, &t.advection, &t.composite, &t.phong};
  for (int i = 0; i < 5; ++i) {
    if (!timerUsed_[i]) continue;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timers_[i].id(), GL_QUERY_RESULT, &ns);
    *out[i] = static_cast<double>(ns) * 1e-6;
  }
  return t;
}

unsigned FabricRenderer::coveredPixels() const { return projection_.coveredPixels(); }

} // namespace dtf::render
