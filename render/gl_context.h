// SPDX-License-Identifier: GPL-3.0-or-later
// The OpenGL 4.5 core context every render path draws with. Batch mode, tests and benchmarks use the
// headless context created here (EGL, no window, no display server); the GUI makes its own GLFW context
// current instead. KHR_debug output is enabled: high and medium severity messages are collected and
// turned into dtf::GlError by checkErrors(), so a GL mistake fails a test instead of going unnoticed.
#pragma once

#include <string>
#include <vector>

namespace dtf::render {

class GlContext {
public:
  // The process's one headless context, created on first use (EGL device platform, then Mesa's
  // surfaceless platform) and made current on the calling thread. Throws GlError when none can be made.
  static GlContext& headless();

  // "renderer / version" of the current context.
  const std::string& description() const { return description_; }
  // Throws GlError naming `where` and listing the severe debug messages (and glGetError codes) collected
  // since the last call; clears them.
  void checkErrors(const std::string& where);
  // Takes the severe messages collected so far without throwing.
  std::vector<std::string> takeMessages();

  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

private:
  GlContext() = default;
  std::string description_;
  friend struct GlContextAccess;
};

// True when the current context's renderer rasterises in software (Mesa's llvmpipe or softpipe,
// SwiftShader): there a pass's cost is its shaded pixels, and the early depth test of a fullscreen draw
// skips the background, so the fabric runs its passes as fragment shaders; on a hardware GPU it runs its
// tensor stage and advection as compute shaders instead (the fragment pipeline of a datacenter GPU is a
// few of its multiprocessors).
bool softwareRasteriser();
// Installs the KHR_debug callback on the current context (done by headless(); the GUI calls it on its
// GLFW context).
void enableDebugOutput();
// Severe messages collected from the debug callback since the last call (any context of this process).
std::vector<std::string> takeDebugMessages();
// Throws GlError naming `where` when severe debug messages or glGetError codes are pending.
void checkGl(const std::string& where);

} // namespace dtf::render
