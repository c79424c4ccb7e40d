// SPDX-License-Identifier: GPL-3.0-or-later
// The desktop viewer's window, the only GLFW user: a GL 4.5 core window, Dear ImGui (GLFW + OpenGL3
// backends), mouse and keys turned into ui actions, script replay, and the scene of app/viewer/viewer.h
// blitted under the panels each frame.
#include "app/viewer/window.h"

#include "app/viewer/portal_dialog.h"
#include "app/viewer/session_file.h"
#include "app/viewer/viewer.h"
#include "app/viewer/viewer_orientation.h"
#include "io/formats/png_io.h"
#include "io/model/error.h"
#include "render/gl_context.h"
#include "ui/panels/panels.h"
#include "ui/session/file_kinds.h"
#include "ui/session/orientation_labels.h"
#include "ui/session/roi_outline.h"
#include "ui/session/surface_spec.h"
#include "ui/session/viewer_config.h"

#include <GLFW/glfw3.h>
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <epoxy/gl.h>
#include <filesystem>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <iostream>
#include <memory>
#include <optional>

namespace dtf::app {

namespace {


constexpr std::size_t kMaxKeys = 64;

struct InputQueue {
  std::array<int, kMaxKeys> keys{};
  std::array<int, kMaxKeys> mods{};
  std::size_t keyCount = 0;
  double scroll = 0;
  int helpChars = 0;                // '?' typed
  std::vector<std::string> dropped; // files dropped on the window since the last frame
};

// The text font of the panels (the figures' font too), from Debian's fonts-dejavu-core.
constexpr const char* kFontFile = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

void onChar(GLFWwindow* w, unsigned int codepoint) {
  if (auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w)); q && codepoint == '?') ++q->helpChars;
}

void onDrop(GLFWwindow* w, int count, const char** paths) {
  auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w));
  if (!q) return;
  for (int i = 0; i < count; ++i)
    if (paths[i]) q->dropped.emplace_back(paths[i]);
}

void onKey(GLFWwindow* w, int key, int, int action, int mods) {
  auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w));
  if (!q || (action != GLFW_PRESS && action != GLFW_REPEAT) || q->keyCount >= kMaxKeys) return;
  q->keys[q->keyCount] = key;
  q->mods[q->keyCount] = mods;
  ++q->keyCount;
}

void onScroll(GLFWwindow* w, double, double dy) {
  if (auto* q = static_cast<InputQueue*>(glfwGetWindowUserPointer(w))) q->scroll += dy;
}

std::optional<session::Key> mapKey(int key) {
  switch (key) {
  case GLFW_KEY_UP:
    return session::Key::Up;
  case GLFW_KEY_DOWN:
    return session::Key::Down;
  case GLFW_KEY_PAGE_UP:
    return session::Key::PageUp;
  case GLFW_KEY_PAGE_DOWN:
    return session::Key::PageDown;
  case GLFW_KEY_A:
    return session::Key::A;
  case GLFW_KEY_C:
    return session::Key::C;
  case GLFW_KEY_S:
    return session::Key::S;
  case GLFW_KEY_R:
    return session::Key::R;
  case GLFW_KEY_F1:
    return session::Key::Help;
  default:
    return std::nullopt;
  }
}

Image readFramebuffer(int x, int y, int w, int h) {
  Image img(w, h);
  std::vector<std::uint8_t> rows(img.rgba.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  const std::size_t stride = static_cast<std::size_t>(w) * 4;
  for (int r = 0; r < h; ++r)
    std::memcpy(&img.rgba[static_cast<std::size_t>(r) * stride],
                &rows[static_cast<std::size_t>(h - 1 - r) * stride], stride);
  for (std::size_t i = 3; i < img.rgba.size(); i += 4)
    img.rgba[i] = 255;
  return img;
}

// SIGINT or SIGTERM asked the window to close: it ends its loop (within the idle wait's 0.25 s) and the
// remembered settings are written as on a normal close.
volatile std::sig_atomic_t closeSignal = 0;
void onCloseSignal(int signal) {
  closeSignal = signal;
}

std::string glfwErrorText;
void onGlfwError(int code, const char* text) {
  glfwErrorText = "GLFW error " + std::to_string(code) + ": " + text;
}

struct GlfwSession {
  GlfwSession() {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) throw GlError("cannot initialise GLFW (is a display available?): " + glfwErrorText);
  }
  ~GlfwSession() { glfwTerminate(); }
};

class ViewerWindow {
public:
  ViewerWindow(int width, int height, const std::string& surface, const ViewScript* script,
               std::optional<double> uiScale)
      : script_(script) {
    explicitScale_ = uiScale;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, "dtfabric", nullptr, nullptr);
    if (!window_) throw GlError("cannot create a GL 4.5 core window: " + glfwErrorText);
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(script ? 0 : 1);
    glfwSetWindowUserPointer(window_, &input_);
    // Installed before ImGui's, which chain to them.
    glfwSetKeyCallback(window_, onKey);
    glfwSetScrollCallback(window_, onScroll);
    glfwSetCharCallback(window_, onChar);
    glfwSetDropCallback(window_, onDrop); // ImGui's backend installs none: nothing to chain
    input_.dropped.reserve(16);
    render::enableDebugOutput();

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // the layout is fixed; no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    baseStyle_ = ImGui::GetStyle();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    ImGui_ImplOpenGL3_CreateDeviceObjects(); // now, so a new font atlas replaces its texture (applyUiScale)
    scene_ = std::make_unique<ViewerScene>(surface);
    applyUiScale(wantedScale());
    // A script's dialogs are the in-window browser (the same on every machine); a person gets the
    // desktop's own where a portal runs.
    if (!script) portal_ = PortalDialog::connect();
    // A script cannot answer the overwrite prompt: its outputs fail instead unless they say --force.
    scene_->setAskBeforeOverwrite(script == nullptr);
    if (script) scene_->addInput(script->file);
    std::snprintf(buffers_.screenshotPath.data(), buffers_.screenshotPath.size(), "dtfabric.png");
    std::snprintf(buffers_.moviePath.data(), buffers_.moviePath.size(), "dtfabric_turntable.mp4");
    std::snprintf(buffers_.cameraPath.data(), buffers_.cameraPath.size(), "dtfabric.camera");
    std::snprintf(buffers_.tractSavePath.data(), buffers_.tractSavePath.size(), "tracts.tck");
    actions_.reserve(32);
  }

  ~ViewerWindow() {
    orientationCheck_.release();
    scene_.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
  }

  ViewerScene& scene() { return *scene_; }
  ui::PanelBuffers& buffers() { return buffers_; }

  // The remembered settings as they are now (ui/session/viewer_config.h).
  session::ViewerConfig config() const {
    session::ViewerConfig c;
    int w = 0, h = 0;
    glfwGetWindowSize(window_, &w, &h);
    if (w >= 320 && h >= 240) {
      c.width = w;
      c.height = h;
    }
    c.uiScale = explicitScale_;
    c.lastFolder = buffers_.browser.lastFolder;
    c.recentFolders = buffers_.browser.recentFolders;
    c.recentFiles = scene_->state().recent;
    c.panelsOpen = buffers_.panelsOpen;
    return c;
  }
  void setOpenPath(const std::string& p) {
    std::snprintf(buffers_.openPath.data(), buffers_.openPath.size(), "%s", p.c_str());
  }
  void setTensorPath(const std::string& p) {
    std::snprintf(buffers_.tensorPath.data(), buffers_.tensorPath.size(), "%s", p.c_str());
  }

  // Runs until the window closes or `quit`; returns the exit code.
  int run() {
    while (!glfwWindowShouldClose(window_) && !quit_ && !closeSignal) {
      const bool idle = scene_->converged() && scene_->settled() && !dragging_ && !runningScript();
      if (idle)
        glfwWaitEventsTimeout(0.25);
      else
        glfwPollEvents();
      // The frame's work, not the idle wait: shown in the status bar and steering the interactive scale.
      const auto t0 = std::chrono::steady_clock::now();
      frame();
      scene_->setFrameMs(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    if (closeSignal) return 128 + closeSignal; // as a shell reports a process ended by the signal
    return scriptFailed_ ? (scene_->glFailed() ? 3 : 2) : 0;
  }

private:
  bool runningScript() const { return script_ && next_ < script_->steps.size(); }

  void frame() {
    if (const double want = wantedScale(); want != uiScale_) applyUiScale(want); // before the layout is used
    int fw = 1, fh = 1, ww = 1, wh = 1;
    glfwGetFramebufferSize(window_, &fw, &fh);
    glfwGetWindowSize(window_, &ww, &wh);
    fw = std::max(fw, 1);
    fh = std::max(fh, 1);
    scale_ = ww > 0 ? static_cast<double>(fw) / ww : 1.0;
    float rect[4];
    ui::sceneRect(layout_, static_cast<float>(ww), static_cast<float>(wh), rect);
    sceneX_ = static_cast<int>(rect[0] * scale_);
    sceneW_ = std::max(static_cast<int>(rect[2] * scale_), 1);
    sceneH_ = std::max(static_cast<int>(rect[3] * scale_), 1);
    sceneY_ = std::max(fh - sceneH_, 0); // GL y of the scene's bottom edge (the status bar lies below)

    handleInput();
    scene_->update();
    stepScript();

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    actions_.clear();
    ui::drawPanels(scene_->state(), buffers_, layout_, actions_);
    takePortalAnswer();
    orientationCheck_.frame(*scene_, rect);
    drawOrientationLabels();
    ImGui::Render();
    for (const auto& a : actions_)
      perform(a);

    scene_->render(sceneW_, sceneH_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    scene_->present(0, sceneX_, sceneY_);
    if (pendingShot_ && pendingShot_->sceneOnly) takeScreenshot(sceneX_, sceneY_, sceneW_, sceneH_);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (pendingShot_) takeScreenshot(0, 0, fw, fh);
    glfwSwapBuffers(window_);
    checkDebugOutput();
    reportNewErrors();
  }

  void takeScreenshot(int x, int y, int w, int h) {
    const session::Screenshot shot = *pendingShot_;
    pendingShot_.reset();
    try {
      if (shot.path.empty()) throw InputError("screenshot: no path given");
      // The ortho layout as a figure: the panes with the crosshair and each slice pane's letters.
      if (shot.sceneOnly && scene_->state().ortho) {
        io::writePng(shot.path, scene_->layoutImage());
      } else {
        Image img = readFramebuffer(x, y, w, h);
        if (shot.sceneOnly) { // the panes as a figure: with their furniture (the window's is drawn by ImGui)
          render::ImageCanvas canvas(img);
          scene_->drawFurniture(canvas);
        }
        io::writePng(shot.path, img);
      }
      std::cerr << "wrote " << shot.path << (shot.sceneOnly ? " (scene)" : " (window)") << "\n";
    } catch (const std::exception& e) {
      scene_->setError(std::string("while saving a screenshot: ") + e.what());
    }
  }

  void perform(const session::Action& a) {
    if (const auto* s = std::get_if<session::Screenshot>(&a)) {
      if (scene_->mayWrite(s->path, s->force, a)) pendingShot_ = *s;
    } else if (const auto* c = std::get_if<session::ConfirmOverwrite>(&a)) {
      if (auto forced = scene_->answerOverwrite(c->overwrite)) perform(*forced);
    } else if (const auto* b = std::get_if<session::Browse>(&a)) {
      browse(*b);
    } else if (const auto* save = std::get_if<session::SaveSession>(&a)) {
      if (scene_->mayWrite(save->path, save->force, a)) saveSession(save->path);
    } else if (const auto* ui = std::get_if<session::SetUiScale>(&a)) {
      explicitScale_ = ui->scale > 0 ? std::optional<double>(std::clamp(ui->scale, 0.5, 4.0)) : std::nullopt;
    } else if (std::holds_alternative<session::Quit>(a)) {
      quit_ = true;
    } else {
      scene_->apply(a);
    }
  }

  // The panels' scale: the one chosen (--ui-scale, View panel, script), else the monitor's content scale.
  double wantedScale() const {
    if (explicitScale_) return *explicitScale_;
    float x = 1, y = 1;
    glfwGetWindowContentScale(window_, &x, &y);
    return std::clamp(std::isfinite(x) && x > 0 ? static_cast<double>(x) : 1.0, 0.5, 4.0);
  }

  // Sizes the panels for `scale`: DejaVu Sans rasterised at the scaled size in a new font atlas (its texture
  // replaced in the OpenGL3 backend), the style's sizes scaled from the unscaled style, and the side and
  // status bars. Runs between frames, only when the scale changes.
  void applyUiScale(double scale) {
    ImGuiIO& io = ImGui::GetIO();
    io.Fonts->Clear();
    const float pixels = std::round(ui::kBaseFontPixels * static_cast<float>(scale));
    std::error_code ec;
    if (std::filesystem::exists(kFontFile, ec)) {
      ImFontConfig font;
      font.OversampleH = 2;
      font.OversampleV = 1;
      io.Fonts->AddFontFromFileTTF(kFontFile, pixels, &font);
    } else { // without fonts-dejavu-core: ImGui's own bitmap font, at its size times the scale
      ImFontConfig font;
      font.SizePixels = std::round(13.0f * static_cast<float>(scale));
      io.Fonts->AddFontDefault(&font);
    }
    ImGui_ImplOpenGL3_DestroyFontsTexture();
    ImGui_ImplOpenGL3_CreateFontsTexture();
    ImGui::GetStyle() = baseStyle_;
    ImGui::GetStyle().ScaleAllSizes(static_cast<float>(scale));
    layout_.setScale(static_cast<float>(scale));
    uiScale_ = scale;
    session::ViewerState& state = scene_->session().state();
    state.uiScale = scale;
    state.uiScaleAuto = !explicitScale_;
  }

  // A file dialog: the desktop portal's where one runs (its answer arrives in takePortalAnswer), else the
  // in-window browser.
  void browse(const session::Browse& b) {
    const std::string folder = b.folder.empty() ? buffers_.browser.lastFolder : b.folder;
    if (portal_ && portal_->ask(b.target, folder)) return;
    ui::openFileBrowser(buffers_.browser, b.target, folder);
  }

  void takePortalAnswer() {
    if (!portal_) return;
    portal_->iterate();
    auto answer = portal_->take();
    if (!answer) return;
    if (!answer->error.empty()) { // the portal failed: the in-window browser instead
      std::cerr << "warning: the desktop's file dialog failed (" << answer->error
                << "); using the viewer's\n";
      ui::openFileBrowser(buffers_.browser, answer->target, buffers_.browser.lastFolder);
    } else if (!answer->path.empty()) {
      ui::rememberFolder(buffers_.browser, answer->path);
      ui::choosePath(buffers_, answer->target, answer->path, actions_);
    }
  }

  // Files dropped on the window (the GLFW drop callback's list, or a script's drop line): each opens by its
  // kind; a file that cannot be opened opens none of them (the error modal names it).
  void drop(const std::vector<std::string>& paths) {
    try {
      const session::ActionList actions = session::dropActions(paths);
      for (const auto& a : actions) {
        if (const auto* load = std::get_if<session::LoadFile>(&a)) {
          setOpenPath(load->path);
          std::cerr << "drop: " << load->path << " opens as data\n";
        } else if (const auto* tracts = std::get_if<session::LoadTracts>(&a)) {
          std::snprintf(buffers_.tractPath.data(), buffers_.tractPath.size(), "%s", tracts->path.c_str());
          std::cerr << "drop: " << tracts->path << " opens as tracts\n";
        } else if (const auto* mesh = std::get_if<session::SetSurfaceSpec>(&a)) {
          std::cerr << "drop: " << mesh->text.substr(5) << " opens as the surface\n";
        }
        perform(a);
      }
    } catch (...) {
      scene_->setError("while opening the dropped files: " + currentExceptionMessage());
    }
  }

  void saveSession(const std::string& path) {
    try {
      int w = 0, h = 0;
      glfwGetWindowSize(window_, &w, &h);
      std::vector<std::string> notes;
      writeSessionFile(path, sessionScript(*scene_, w, h, explicitScale_, &notes));
      std::cerr << "wrote " << path << " (session)\n";
      for (const auto& n : notes)
        std::cerr << "note: the session does not restore " << n << "\n";
    } catch (...) {
      scene_->setError("while saving the session " + path + ": " + currentExceptionMessage());
    }
  }

  bool inScene(double x, double y) const {
    const double fx = x * scale_, fy = y * scale_;
    return fx >= sceneX_ && fx < sceneX_ + sceneW_ && fy >= 0 && fy < sceneH_;
  }

  void handleInput() {
    const ImGuiIO& io = ImGui::GetIO();
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const bool left = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    const bool middle = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
    const bool shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                       glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    // Ortho layout: regions. A press in a slice pane places one (the panel's place mode) or grabs the one
    // under the cursor, which follows the cursor within the slice's plane until released.
    const double sx = x * scale_ - sceneX_, sy = y * scale_;
    if (!left) {
      regionDrag_ = -1;
      regionPress_ = false;
    }
    if (left && !dragging_ && !crossDragging_ && regionDrag_ < 0 && !regionPress_ && !io.WantCaptureMouse &&
        inScene(x, y)) {
      const int pane = scene_->orthoPaneAt(sx, sy);
      if (pane >= 0 && buffers_.roiPlace != 0) {
        const glm::dvec3 at = scene_->orthoWorld(pane, sx, sy);
        session::RoiAdd add;
        add.kind = add.region.kind = static_cast<surfaces::RegionKind>(std::clamp(buffers_.roiKind, 0, 2));
        const double size = buffers_.roiSizeMm;
        if (buffers_.roiPlace == 1) {
          add.region.shape = surfaces::RegionShape::Sphere;
          add.region.centre = at;
          add.region.radius = size;
        } else {
          add.region.shape = surfaces::RegionShape::Box;
          add.region.lo = at - glm::dvec3(size);
          add.region.hi = at + glm::dvec3(size);
        }
        buffers_.roiPlace = 0;
        regionPress_ = true;
        perform(add);
      } else if (pane >= 0) {
        const int i = scene_->regionAt(sx, sy);
        if (i >= 0) {
          regionDrag_ = i;
          regionPane_ = pane;
          regionFrom_ = scene_->orthoWorld(pane, sx, sy);
          regionStart_ = scene_->state().roiSet.regions[std::size_t(i)];
          lastX_ = x;
          lastY_ = y;
        }
      }
    }
    if (regionDrag_ >= 0 && (x != lastX_ || y != lastY_) &&
        std::size_t(regionDrag_) < scene_->state().roiSet.regions.size()) {
      perform(scene_->regionDragged(std::size_t(regionDrag_), regionStart_, regionPane_, regionFrom_, sx, sy));
      lastX_ = x;
      lastY_ = y;
    }
    // Ortho layout: a left press (and drag) in a slice pane moves the crosshair.
    if (regionDrag_ >= 0 || regionPress_) {
      // the press belongs to a region
    } else if (left && !dragging_ && !io.WantCaptureMouse && inScene(x, y) &&
               (crossDragging_ || scene_->orthoPaneAt(x * scale_ - sceneX_, y * scale_) >= 0)) {
      if (x != lastX_ || y != lastY_ || !crossDragging_) scene_->clickAt(x * scale_ - sceneX_, y * scale_);
      crossDragging_ = true;
      lastX_ = x;
      lastY_ = y;
    } else if (!left) {
      crossDragging_ = false;
    }
    if (!crossDragging_ && !dragging_ && (left || middle) && !io.WantCaptureMouse && inScene(x, y)) {
      dragging_ = true;
      panning_ = middle || shift;
      dragPane_ = scene_->paneAt(x * scale_ - sceneX_);
      scene_->setActivePane(dragPane_);
      lastX_ = x;
      lastY_ = y;
    } else if (dragging_ && !left && !middle) {
      dragging_ = false;
    }
    scene_->setInteracting(dragging_);
    if (dragging_ && (x != lastX_ || y != lastY_)) {
      const double dx = (x - lastX_) * scale_, dy = (y - lastY_) * scale_;
      if (panning_)
        scene_->apply(session::Pan{dx, dy, dragPane_});
      else
        scene_->apply(session::Rotate{dx, dy, dragPane_});
      lastX_ = x;
      lastY_ = y;
    }
    if (input_.scroll != 0 && !io.WantCaptureMouse && inScene(x, y)) {
      // Over a region in a slice pane the wheel grows or shrinks it about its centre; elsewhere it zooms.
      if (const auto set = scene_->regionScaled(sx, sy, input_.scroll)) {
        perform(*set);
      } else {
        scene_->apply(session::Zoom{std::pow(1.15, input_.scroll), scene_->paneAt(x * scale_ - sceneX_)});
      }
    }
    input_.scroll = 0;
    for (std::size_t i = 0; i < input_.keyCount; ++i) {
      if (io.WantCaptureKeyboard) break;
      if (input_.keys[i] == GLFW_KEY_ESCAPE && !scene_->state().errorChain.empty())
        scene_->apply(session::DismissError{});
      if (auto k = mapKey(input_.keys[i]); k && !(input_.mods[i] & (GLFW_MOD_CONTROL | GLFW_MOD_ALT)))
        scene_->applyKey(*k);
    }
    input_.keyCount = 0;
    for (; input_.helpChars > 0; --input_.helpChars)
      if (!io.WantCaptureKeyboard) scene_->applyKey(session::Key::Help);
    if (!input_.dropped.empty()) {
      drop(input_.dropped);
      input_.dropped.clear();
    }
    if ((x != probeX_ || y != probeY_) && inScene(x, y)) {
      scene_->probe(x * scale_ - sceneX_, y * scale_);
      probeX_ = x;
      probeY_ = y;
    }
  }

  // The scene area of the window as a canvas for the figure furniture (scene pixels; ImGui draws in window
  // points).
  class ImGuiCanvas final : public render::Canvas {
  public:
    ImGuiCanvas(ImDrawList* dl, int x0, int w, int h, double scale) : dl_(dl), x0_(x0), w_(w), h_(h), inv_(1.0 / scale) {}
    int width() const override { return w_; }
    int height() const override { return h_; }
    void fill(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) override {
      const auto px = [&](int v) { return static_cast<float>(v * inv_); };
      dl_->AddRectFilled(ImVec2(px(x0_ + x), px(y)), ImVec2(px(x0_ + x + w), px(y + h)), IM_COL32(r, g, b, 255));
    }
    void blend(int x, int y, int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
               std::uint8_t alpha) override {
      const auto px = [&](int v) { return static_cast<float>(v * inv_); };
      dl_->AddRectFilled(ImVec2(px(x0_ + x), px(y)), ImVec2(px(x0_ + x + w), px(y + h)), IM_COL32(r, g, b, alpha));
    }

  private:
    ImDrawList* dl_;
    int x0_, w_, h_;
    double inv_;
  };

  // The anatomical letters at the four edges of a pane (screen points x0, y0 .. x1, y1), from its camera.
  static void drawPaneLetters(ImDrawList* dl, const render::Camera& c, float x0, float y0, float x1, float y1) {
    const glm::dvec3 right = c.right(), up = glm::normalize(glm::cross(right, c.forward()));
    const float mx = 0.5f * (x0 + x1), my = 0.5f * (y0 + y1);
    const struct {
      const char* text;
      ImVec2 at;
    } labels[4] = {{session::anatomicalLabel(right), ImVec2(x1 - ui::em(16), my - ui::em(7))},
                   {session::anatomicalLabel(-right), ImVec2(x0 + ui::em(8), my - ui::em(7))},
                   {session::anatomicalLabel(up), ImVec2(mx - ui::em(4), y0 + ui::em(6))},
                   {session::anatomicalLabel(-up), ImVec2(mx - ui::em(4), y1 - ui::em(20))}};
    for (const auto& l : labels) {
      dl->AddText(ImVec2(l.at.x + 1, l.at.y + 1), IM_COL32(0, 0, 0, 255), l.text);
      dl->AddText(l.at, IM_COL32(255, 230, 90, 255), l.text);
    }
  }

  // The regions as translucent shapes over a 3D pane (window pixels x0..x1, y0..y1): a sphere as its
  // silhouette's disc, a box as its faces and edges, a mask as its voxels' surface with its creases (past
  // session::kMaskFaceCap faces, the box of its bounds), in their kind's colour. Drawn over the scene, not
  // depth-tested against the surface.
  void drawRegions3d(ImDrawList* dl, int p, float x0, float y0, float x1, float y1) {
    const session::ViewerState& st = scene_->state();
    if (st.roiSet.regions.empty()) return;
    const render::Camera& cam = scene_->camera(p);
    const double w = x1 - x0, h = y1 - y0;
    const ViewerScene::PaneProjection toPane = scene_->paneProjection(p, w, h);
    auto project = [&](const glm::dvec3& world, ImVec2& out) {
      glm::dvec2 px;
      if (!toPane(world, px)) return false;
      out = ImVec2(static_cast<float>(x0 + px.x), static_cast<float>(y0 + px.y));
      return true;
    };
    dl->PushClipRect(ImVec2(x0, y0), ImVec2(x1, y1), true);
    const glm::dvec3 up = glm::normalize(glm::cross(cam.right(), cam.forward()));
    for (std::size_t i = 0; i < st.roiSet.regions.size(); ++i) {
      if (i < st.roiVisible.size() && !st.roiVisible[i]) continue;
      const surfaces::Region& r = st.roiSet.regions[i];
      const glm::u8vec3 k = session::regionKindColour(r.kind);
      const ImU32 fill = IM_COL32(k.x, k.y, k.z, 60), line = IM_COL32(k.x, k.y, k.z, 220);
      if (r.shape == surfaces::RegionShape::Sphere) {
        ImVec2 c, top;
        if (!project(r.centre, c) || !project(r.centre + r.radius * up, top)) continue;
        const float radius = std::hypot(top.x - c.x, top.y - c.y);
        dl->AddCircleFilled(c, radius, fill, 48);
        dl->AddCircle(c, radius, line, 48, 1.5f);
      } else {
        glm::dvec3 lo = r.lo, hi = r.hi;
        if (r.shape == surfaces::RegionShape::Mask) {
          const session::MaskSurface& s = scene_->maskSurface(r);
          if (s.drawn) {
            ImVec2 q[4];
            for (std::size_t f = 0; f + 3 < s.faces.size(); f += 4)
              if (project(s.faces[f], q[0]) && project(s.faces[f + 1], q[1]) && project(s.faces[f + 2], q[2]) &&
                  project(s.faces[f + 3], q[3]))
                dl->AddQuadFilled(q[0], q[1], q[2], q[3], IM_COL32(k.x, k.y, k.z, 25));
            for (std::size_t e = 0; e + 1 < s.creases.size(); e += 2)
              if (project(s.creases[e], q[0]) && project(s.creases[e + 1], q[1]))
                dl->AddLine(q[0], q[1], line, 1.5f);
            continue;
          }
          lo = s.lo, hi = s.hi;
        }
        ImVec2 q[8];
        bool ok = true;
        for (int j = 0; j < 8; ++j)
          ok &= project(session::boxCorner(lo, hi, j), q[j]);
        if (!ok) continue;
        for (const auto& f : session::kBoxFaces) {
          dl->AddQuadFilled(q[f[0]], q[f[1]], q[f[2]], q[f[3]], IM_COL32(k.x, k.y, k.z, 25));
          dl->AddQuad(q[f[0]], q[f[1]], q[f[2]], q[f[3]], line, 1.5f);
        }
      }
    }
    dl->PopClipRect();
  }

  void drawOrientationLabels() {
    if (!scene_->state().hasData) return;
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    ImGuiCanvas canvas(dl, sceneX_, sceneW_, sceneH_, scale_);
    scene_->drawFurniture(canvas, uiScale_); // the furniture over the window follows the UI scale
    const float inv = static_cast<float>(1.0 / scale_);
    for (int p = 0; p < scene_->paneCount(); ++p) {
      const auto r = scene_->paneRect(p);
      const float x0 = (sceneX_ + r[0]) * inv, y0 = r[1] * inv, x1 = x0 + r[2] * inv, y1 = y0 + r[3] * inv;
      drawPaneLetters(dl, scene_->camera(p), x0, y0, x1, y1);
      if (p == 1) dl->AddLine(ImVec2(x0, y0), ImVec2(x0, y1), IM_COL32(90, 90, 90, 255), 2.0f);
      drawRegions3d(dl, p, x0, y0, x1, y1);
    }
    if (!scene_->state().ortho) return;
    for (int s = 0; s < 3; ++s) {
      const auto r = scene_->orthoRect(s);
      const float x0 = (sceneX_ + r[0]) * inv, y0 = r[1] * inv, x1 = x0 + r[2] * inv, y1 = y0 + r[3] * inv;
      const glm::dvec2 at = scene_->orthoPixel(s, scene_->state().crosshair);
      const float cx = static_cast<float>((sceneX_ + at.x) * inv), cy = static_cast<float>(at.y * inv);
      dl->PushClipRect(ImVec2(x0, y0), ImVec2(x1, y1), true);
      dl->AddLine(ImVec2(x0, cy), ImVec2(x1, cy), IM_COL32(255, 230, 90, 200), 1.0f);
      dl->AddLine(ImVec2(cx, y0), ImVec2(cx, y1), IM_COL32(255, 230, 90, 200), 1.0f);
      // The regions' outlines where they cut this slice.
      const auto& regions = scene_->state().roiSet.regions;
      for (std::size_t i = 0; i < regions.size(); ++i) {
        bool segments = false;
        if (!scene_->regionOutlinePixels(s, i, outlinePx_, &segments)) continue;
        outlineIm_.clear();
        for (const glm::dvec2& p : outlinePx_)
          outlineIm_.push_back(
              ImVec2(static_cast<float>((sceneX_ + p.x) * inv), static_cast<float>(p.y * inv)));
        const glm::u8vec3 c = session::regionKindColour(regions[i].kind);
        if (segments) // a mask's outline: lattice edges
          for (std::size_t k = 0; k + 1 < outlineIm_.size(); k += 2)
            dl->AddLine(outlineIm_[k], outlineIm_[k + 1], IM_COL32(c.x, c.y, c.z, 255), 2.0f);
        else
          dl->AddPolyline(outlineIm_.data(), static_cast<int>(outlineIm_.size()), IM_COL32(c.x, c.y, c.z, 255),
                          ImDrawFlags_Closed, 2.0f);
      }
      dl->PopClipRect();
      drawPaneLetters(dl, scene_->orthoCamera(s), x0, y0, x1, y1);
    }
    const auto r0 = scene_->paneRect(0);
    const float gx = (sceneX_ + r0[0]) * inv, gy = r0[1] * inv;
    dl->AddLine(ImVec2(gx, 0), ImVec2(gx, (r0[1] + r0[3]) * inv), IM_COL32(90, 90, 90, 255), 2.0f);
    dl->AddLine(ImVec2(sceneX_ * inv, gy), ImVec2((sceneX_ + r0[0] + r0[2]) * inv, gy), IM_COL32(90, 90, 90, 255),
                2.0f);
  }

  void printCrosshair(int line) {
    const session::ViewerState& s = scene_->state();
    std::fprintf(stderr, "%s:%d: crosshair %.2f %.2f %.2f mm, slices axial %d coronal %d sagittal %d\n",
                 script_->file.c_str(), line, s.crosshair.x, s.crosshair.y, s.crosshair.z, s.orthoSlice[0],
                 s.orthoSlice[1], s.orthoSlice[2]);
  }

  void checkDebugOutput() {
    auto messages = render::takeDebugMessages();
    if (messages.empty()) return;
    std::string text = "GL debug output: " + messages.front();
    if (messages.size() > 1) text += " (and " + std::to_string(messages.size() - 1) + " more)";
    scene_->setError(text);
  }

  void reportNewErrors() {
    if (scene_->errorSerial() == reportedErrors_) return;
    reportedErrors_ = scene_->errorSerial();
    std::string text;
    for (const auto& link : scene_->state().errorChain)
      text += (text.empty() ? "" : ": ") + link;
    if (script_) {
      std::cerr << script_->file << ":" << lastLine_ << ": error: " << text << "\n";
      scriptFailed_ = true;
    } else {
      std::cerr << "error: " << text << "\n";
    }
  }

  // Replays script steps: each waits until the worker is idle, a screenshot also until the fabric
  // converged (so screenshots are deterministic); `wait N` renders N frames.
  void stepScript() {
    if (!runningScript()) return;
    if (waitFrames_ > 0) {
      --waitFrames_;
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    while (runningScript()) {
      const ScriptStep& step = script_->steps[next_];
      const auto* action = std::get_if<session::Action>(&step.command);
      const bool shot = action && std::holds_alternative<session::Screenshot>(*action);
      const bool probe = std::holds_alternative<ScriptProbe>(step.command);
      // track-cancel is meant for the running tracking: it does not wait for the worker.
      const bool cancel = action && std::holds_alternative<session::CancelTracking>(*action);
      // Screenshots and probes read the rendered image: they wait for the fabric to converge.
      const bool ready = cancel || (scene_->settled() && (!(shot || probe) || scene_->converged()));
      if (!ready) {
        if (!waitingSince_) waitingSince_ = now;
        if (std::chrono::duration<double>(now - *waitingSince_).count() < kStepTimeoutSeconds) return;
        std::cerr << script_->file << ":" << step.line << ": warning: still busy after "
                  << kStepTimeoutSeconds << " s; going on\n";
      }
      waitingSince_.reset();
      // ImGui lays out a newly opened window (the error modal, say) one frame before drawing it.
      if (shot && shotDelay_ < 2) {
        ++shotDelay_;
        return;
      }
      shotDelay_ = 0;
      lastLine_ = step.line;
      ++next_;
      if (action) {
        const auto errorsBefore = scene_->errorSerial();
        perform(*action);
        if (std::holds_alternative<session::SetCrosshair>(*action)) printCrosshair(step.line);
        if (shot || std::holds_alternative<session::Quit>(*action)) return;
        if (scene_->errorSerial() != errorsBefore)
          return;                       // reported at the end of this frame, with this line
        if (!scene_->settled()) return; // started work on the worker
        // An error is reported at the end of this frame with lastLine_: this line's, not a later one's.
        if (scene_->errorSerial() != reportedErrors_) return;
      } else if (const auto* key = std::get_if<session::Key>(&step.command)) {
        scene_->applyKey(*key);
        if (!scene_->settled()) return;
      } else if (const auto* wait = std::get_if<ScriptWait>(&step.command)) {
        waitFrames_ = wait->frames;
        return;
      } else if (const auto* size = std::get_if<ScriptResize>(&step.command)) {
        glfwSetWindowSize(window_, size->width, size->height);
        waitFrames_ = 2; // the new size arrives with the next events
        return;
      } else if (const auto* click = std::get_if<ScriptClick>(&step.command)) {
        if (!scene_->clickAt(click->x, click->y))
          std::fprintf(stderr, "%s:%d: click %g %g: not in a slice pane of the ortho layout\n",
                       script_->file.c_str(), step.line, click->x, click->y);
        printCrosshair(step.line);
      } else if (const auto* at = std::get_if<ScriptProbe>(&step.command)) {
        scene_->probe(at->x, at->y);
        const session::ProbeInfo& p = scene_->state().probe;
        std::fprintf(stderr, "%s:%d: probe %g %g: ", script_->file.c_str(), step.line, at->x, at->y);
        if (!p.onSurface)
          std::fprintf(stderr, "background\n");
        else if (!p.inData)
          std::fprintf(stderr, "surface at %.2f %.2f %.2f mm, outside the data\n", p.world.x, p.world.y,
                       p.world.z);
        else
          std::fprintf(stderr, "surface at %.2f %.2f %.2f mm, %s\n", p.world.x, p.world.y, p.world.z,
                       p.text.c_str());
      } else if (const auto* pick = std::get_if<ScriptBrowserPick>(&step.command)) {
        const bool open = buffers_.browser.open;
        if (!ui::pickInBrowser(buffers_, pick->name, actions_))
          scene_->setError("browser-pick " + pick->name + ": " +
                           (open ? buffers_.browser.pickError : std::string("the file browser is not open")));
        for (const auto& a : actions_)
          perform(a);
        actions_.clear();
        return; // the browser's new folder or the chosen file's work shows next frame
      } else if (const auto* dropped = std::get_if<ScriptDrop>(&step.command)) {
        drop(dropped->paths);
        return;
      } else if (const auto* param = std::get_if<ScriptSetParam>(&step.command)) {
        render::FabricParams p = scene_->state().fabric;
        applyScriptParam(p, *param);
        scene_->apply(session::SetFabricParams{p});
      }
    }
  }

  static constexpr double kStepTimeoutSeconds = 120;

  GLFWwindow* window_ = nullptr;
  InputQueue input_;
  std::unique_ptr<ViewerScene> scene_;
  ViewerOrientation orientationCheck_; // the check's banner over the scene
  ui::PanelBuffers buffers_;
  ui::PanelLayout layout_;
  ImGuiStyle baseStyle_;                 // the style at scale 1
  std::optional<double> explicitScale_;  // --ui-scale, the View panel or a script; none: the monitor's
  double uiScale_ = 0;                   // the scale the fonts and style were built for
  std::unique_ptr<PortalDialog> portal_; // the desktop's file dialog; null: none runs (or a script)
  session::ActionList actions_;
  std::optional<session::Screenshot> pendingShot_;
  bool quit_ = false;
  double scale_ = 1;
  int sceneX_ = 0, sceneY_ = 0, sceneW_ = 1, sceneH_ = 1;
  bool dragging_ = false, panning_ = false, crossDragging_ = false;
  int dragPane_ = 0;
  // A region dragged in a slice pane: its index, pane, the world point grabbed and the region as it was.
  int regionDrag_ = -1, regionPane_ = -1;
  bool regionPress_ = false; // the left press placed a region: ignored until released
  glm::dvec3 regionFrom_{0.0};
  surfaces::Region regionStart_;
  std::vector<glm::dvec2> outlinePx_; // scratch for the outlines drawn each frame
  std::vector<ImVec2> outlineIm_;
  double lastX_ = 0, lastY_ = 0, probeX_ = -1, probeY_ = -1;
  const ViewScript* script_ = nullptr;
  std::size_t next_ = 0;
  int waitFrames_ = 0, shotDelay_ = 0;
  int lastLine_ = 0;
  std::optional<std::chrono::steady_clock::time_point> waitingSince_;
  std::uint64_t reportedErrors_ = 0;
  bool scriptFailed_ = false;
};

} // namespace

int runViewerWindow(const ViewerWindowOptions& o) {
  // The remembered settings: a flag given wins over them.
  session::ViewerConfig remembered;
  if (!o.configPath.empty()) {
    std::vector<std::string> warnings;
    remembered = session::readViewerConfig(o.configPath, &warnings);
    for (const auto& w : warnings)
      std::cerr << "warning: viewer settings: " << w << "\n";
  }
  const session::StartSettings start = session::mergeConfig(
      remembered, o.sizeGiven || o.configPath.empty() ? std::optional<int>(o.width) : std::nullopt,
      o.sizeGiven || o.configPath.empty() ? std::optional<int>(o.height) : std::nullopt, o.uiScale);
  if (!o.configPath.empty())
    std::cerr << "settings: " << o.configPath << " (window " << start.width << "x" << start.height << ", UI scale "
              << (start.uiScale ? std::to_string(*start.uiScale).substr(0, 4) : std::string("of the monitor"))
              << ")\n";
  GlfwSession glfw;
  ViewerWindow window(start.width, start.height, o.surface, o.script, start.uiScale);
  closeSignal = 0;
  const auto previousInt = std::signal(SIGINT, onCloseSignal), previousTerm = std::signal(SIGTERM, onCloseSignal);
  window.buffers().browser.lastFolder = remembered.lastFolder;
  window.buffers().browser.recentFolders = remembered.recentFolders;
  window.buffers().panelsOpen = remembered.panelsOpen;
  for (auto it = remembered.recentFiles.rbegin(); it != remembered.recentFiles.rend(); ++it)
    window.scene().addRecent(*it);
  for (auto it = o.inputs.rbegin(); it != o.inputs.rend(); ++it)
    window.scene().addRecent(*it);
  if (o.uncertainty) window.scene().setUncertainty(*o.uncertainty);
  if (o.ortho) window.scene().apply(session::SetOrtho{true});
  window.scene().apply(o.furniture);
  if (!o.background.what.empty()) window.scene().apply(o.background);
  if (!o.inputs.empty()) {
    window.setOpenPath(o.inputs.front());
    window.setTensorPath(o.tensor);
    window.scene().apply(session::LoadFile{o.inputs.front(), o.layout, o.tensor});
  }
  if (!o.fabricAlong.path.empty()) {
    window.scene().apply(session::LoadTracts{o.fabricAlong.path});
    window.scene().apply(session::SetFabricAlong{true, o.fabricAlong.mm});
  }
  const int code = window.run();
  std::signal(SIGINT, previousInt);
  std::signal(SIGTERM, previousTerm);
  if (!o.configPath.empty()) {
    try {
      session::writeViewerConfig(o.configPath, window.config());
    } catch (const std::exception& e) {
      std::cerr << "warning: the viewer settings were not saved: " << e.what() << "\n";
    }
  }
  return code;
}

} // namespace dtf::app
