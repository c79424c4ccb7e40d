#include "app/viewer/viewer.h"

#include "ui/session/fibre_input.h"
#include "ui/session/tract_overlay.h"
#include "io/formats/atomic_file.h"
#include "io/model/error.h"
#include "render/gl_context.h"

#include <algorithm>
#include <cmath>
#include <epoxy/gl.h>
#include <fstream>
#include <glm/gtc/matrix_inverse.hpp>

namespace dtf::app {

namespace {

constexpr int kStillIterations = 12;    // advection iterations per frame once the camera is still
constexpr double kMotionSeconds = 0.15; // a camera change keeps frames interactive this long
constexpr double kTargetFrameMs = 66;   // interactive frame time the resolution adapts to (15 fps)

} // namespace

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
  return true;
}

bool ViewerScene::paneShowsTracts(int p) const {
  if (!state().tractsVisible || !tractRenderer_ || tractRenderer_->segmentCount(0) == 0) return false;
  return !(state().split && state().secondPane == session::SecondPane::Tracts && p == 0);
}

std::array<int, 4> ViewerScene::paneRect(int p) const {
  if (!state().split) return {0, 0, width_, height_};
  const int half = std::max(width_ / 2, 1);
  return p == 0 ? std::array<int, 4>{0, 0, half, height_}
                : std::array<int, 4>{half, 0, std::max(width_ - half, 1), height_};
}

int ViewerScene::paneAt(double x) const {
  return state().split && x >= paneRect(1)[0] ? 1 : 0;
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

render::FabricRenderer& ViewerScene::upToDate(std::unique_ptr<render::FabricRenderer>& r, int slot) {
  const auto data = session_.dataset();
  const bool principal = data && !data->fibres && state().fabric.colour == render::ColourMode::Fibres;
  if (data && (fieldUploaded_[slot] != session_.fieldSerial() || principalUploaded_[slot] != principal)) {
    if (fieldUploaded_[slot] != session_.fieldSerial()) r->setField(data->loaded.field);
    if (data->fibres) {
      r->setFibres(data->fibres->set, data->fa.data.empty() ? nullptr : &data->fa);
    } else if (principal) {
      // A tensor in the fibres colour mode: its principal directions as one population, as `render` does.
      if (!principal_ || principalSerial_ != session_.fieldSerial()) {
        principal_ = session::principalFibres(data->loaded.field);
        principalSerial_ = session_.fieldSerial();
      }
      r->setFibres(*principal_);
    } else {
      r->clearFibres();
    }
    fieldUploaded_[slot] = session_.fieldSerial();
    principalUploaded_[slot] = principal;
  }
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
    setView(session_.homeView());
  }
  if (session_.meshSerial() != seenMesh_) {
    seenMesh_ = session_.meshSerial();
    cameraChanged(); // a new mesh while sweeping counts as motion: interactive frames, not still refinement
  }
  if (session_.displaySerial() != seenDisplay_ && session_.tractDisplay()) {
    seenDisplay_ = session_.displaySerial();
    try {
      if (!tractRenderer_) tractRenderer_ = std::make_unique<render::TractRenderer>();
      if (session_.tractDisplay() != uploaded_) {
        tractRenderer_->upload(*session_.tractDisplay());
        uploaded_ = session_.tractDisplay();
      }
    } catch (...) {
      session_.setError("while uploading the tracts: " + currentExceptionMessage());
    }
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
      render::FabricParams params = state.fabric;
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
    glBlitNamedFramebuffer(outputFbo_[p], fbo, 0, 0, src.x, src.y, x + rect[0], y, x + rect[0] + rect[2],
                           y + rect[3], GL_COLOR_BUFFER_BIT, same ? GL_NEAREST : GL_LINEAR);
  }
}

void ViewerScene::probe(double x, double y) {
  session_.clearProbe();
  if (!session_.mesh() || !session_.dataset()) return;
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
