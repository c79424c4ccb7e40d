// SPDX-License-Identifier: GPL-3.0-or-later
// The only file that talks to EGL. Headless GL 4.5 core: eglGetPlatformDisplayEXT (through libepoxy; the
// EGL 1.5 entry point fails before a display exists) on EGL_PLATFORM_DEVICE_EXT first, then Mesa's
// surfaceless platform; a context without config (EGL_KHR_no_config_context) made current without a
// surface. 4.6 is not requested because llvmpipe refuses it.
#include "render/gl_context.h"

#include "io/model/error.h"
#include "io/model/log.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <mutex>
#include <sstream>

namespace dtf::render {

namespace {

std::mutex gMessagesMutex;
std::vector<std::string> gMessages;

void APIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                            const GLchar* message, const void*) {
  (void)source;
  if (severity != GL_DEBUG_SEVERITY_HIGH && severity != GL_DEBUG_SEVERITY_MEDIUM) return;
  // Only misuse counts: drivers also report performance hints at medium severity (NVIDIA: "shader
  // recompiled based on GL state" on a cold shader cache), which are not errors.
  if (type != GL_DEBUG_TYPE_ERROR && type != GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR &&
      type != GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR)
    return;
  std::ostringstream s;
  s << (severity == GL_DEBUG_SEVERITY_HIGH ? "[high] " : "[medium] ") << "type 0x" << std::hex << type
    << " id " << std::dec << id << ": " << std::string(message, length > 0 ? length : 0);
  std::lock_guard lock(gMessagesMutex);
  if (gMessages.size() < 64) gMessages.push_back(s.str());
}

EGLDisplay tryDisplay(EGLenum platform, void* native, std::string& why) {
  EGLDisplay dpy = eglGetPlatformDisplayEXT(platform, native, nullptr);
  if (dpy == EGL_NO_DISPLAY) {
    why += " eglGetPlatformDisplayEXT failed (0x" + std::to_string(eglGetError()) + ");";
    return EGL_NO_DISPLAY;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor)) {
    why += " eglInitialize failed;";
    return EGL_NO_DISPLAY;
  }
  return dpy;
}

bool tryContext(EGLDisplay dpy, std::string& why) {
  if (!epoxy_has_egl_extension(dpy, "EGL_KHR_no_config_context") &&
      !epoxy_has_egl_extension(dpy, "EGL_MESA_configless_context")) {
    why += " no configless context extension;";
    return false;
  }
  if (!epoxy_has_egl_extension(dpy, "EGL_KHR_surfaceless_context")) {
    why += " no surfaceless context extension;";
    return false;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why += " eglBindAPI(OpenGL) failed;";
    return false;
  }
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                            EGL_CONTEXT_OPENGL_DEBUG, std::getenv("DTF_GL_NO_DEBUG") ? EGL_FALSE : EGL_TRUE, EGL_NONE};
  EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  if (ctx == EGL_NO_CONTEXT) {
    why += " eglCreateContext(4.5 core) failed;";
    return false;
  }
  if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
    eglDestroyContext(dpy, ctx);
    why += " eglMakeCurrent failed;";
    return false;
  }
  if (epoxy_gl_version() < 45) {
    why += " context is below GL 4.5;";
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    return false;
  }
  return true;
}

} // namespace

struct GlContextAccess {
  static GlContext* create() {
    std::string why;
    bool ok = false;
    EGLDisplay noDisplay = EGL_NO_DISPLAY;
    if (epoxy_has_egl_extension(noDisplay, "EGL_EXT_platform_device") &&
        epoxy_has_egl_extension(noDisplay, "EGL_EXT_device_enumeration")) {
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (eglQueryDevicesEXT(16, devices, &count)) {
        for (EGLint i = 0; i < count && !ok; ++i) {
          EGLDisplay dpy = tryDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], why);
          if (dpy != EGL_NO_DISPLAY) ok = tryContext(dpy, why);
        }
      } else {
        why += " eglQueryDevicesEXT failed;";
      }
    } else {
      why += " no EGL device platform;";
    }
    if (!ok && epoxy_has_egl_extension(noDisplay, "EGL_MESA_platform_surfaceless")) {
      EGLDisplay dpy = tryDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, why);
      if (dpy != EGL_NO_DISPLAY) ok = tryContext(dpy, why);
    }
    if (!ok) throw GlError("cannot create a headless OpenGL 4.5 core context through EGL:" + why);
    auto* c = new GlContext();
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    c->description_ = std::string(renderer ? renderer : "?") + " / " + (version ? version : "?");
    if (!std::getenv("DTF_GL_NO_DEBUG")) enableDebugOutput();
    logInfo("headless GL: " + c->description_);
    return c;
  }
};

GlContext& GlContext::headless() {
  // Created once; a failure is remembered so every caller sees the same error without retrying EGL.
  static std::string failure;
  static GlContext* instance = [] {
    try {
      return GlContextAccess::create();
    } catch (const GlError& e) {
      failure = e.what();
      return static_cast<GlContext*>(nullptr);
    }
  }();
  if (!instance) throw GlError(failure);
  return *instance;
}

void GlContext::checkErrors(const std::string& where) { checkGl(where); }
std::vector<std::string> GlContext::takeMessages() { return takeDebugMessages(); }

bool softwareRasteriser() {
  const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (!r) return true;
  const std::string renderer(r);
  for (const char* name : {"llvmpipe", "softpipe", "SwiftShader", "Software Rasterizer"})
    if (renderer.find(name) != std::string::npos) return true;
  return false;
}

void enableDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(debugCallback, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

std::vector<std::string> takeDebugMessages() {
  std::lock_guard lock(gMessagesMutex);
  std::vector<std::string> out;
  out.swap(gMessages);
  return out;
}

void checkGl(const std::string& where) {
  std::vector<std::string> msgs = takeDebugMessages();
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    std::ostringstream s;
    s << "glGetError 0x" << std::hex << e;
    msgs.push_back(s.str());
    if (msgs.size() > 64) break;
  }
  if (msgs.empty()) return;
  std::string text = where + ":";
  for (const auto& m : msgs) text += "\n  " + m;
  throw GlError(text);
}

} // namespace dtf::render
