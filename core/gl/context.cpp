#include "core/gl/context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/gl/stage_profile.h"
#include "core/progress.h"

namespace isoatlas::gl {
namespace {

std::string g_debugError;  // first error message from GL debug output since the last checkErrors()
thread_local Context* t_current = nullptr;  // the context of ours this thread last made current
std::atomic<int> g_made{0};
std::atomic<std::uint64_t> g_serials{0};

[[maybe_unused]] void GLAPIENTRY onDebugMessage(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                               const void*) {
  if ((type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH) && g_debugError.empty())
    g_debugError = message;
  noteDriverMessage(type, message);  // ISOATLAS_GL_PROFILE=1 only
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

struct EglAttempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

// Initialises `display` and makes a GL 4.5 core context current on it without a surface.
bool tryDisplay(EGLDisplay display, EglAttempt& out) {
  if (display == EGL_NO_DISPLAY) return false;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return false;
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    return false;
  }
  const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  const bool noConfig = hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
  if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count < 1) {
    if (!noConfig) {
      eglTerminate(display);
      return false;
    }
    config = EGL_NO_CONFIG_KHR;
  }
#ifdef NDEBUG
  const EGLint debug = EGL_FALSE;
#else
  const EGLint debug = EGL_TRUE;
#endif
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_CONTEXT_OPENGL_DEBUG, debug, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
    return false;
  }
  out = {display, context};
  return true;
}

// Real devices first (a GPU driver), Mesa's software device last.
bool tryDevices(EglAttempt& out, std::string& platform) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(client, "EGL_EXT_platform_device") || !hasExtension(client, "EGL_EXT_device_enumeration"))
    return false;
  EGLint count = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return false;
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  eglQueryDevicesEXT(count, devices.data(), &count);
  for (int pass = 0; pass < 2; ++pass) {
    for (EGLDeviceEXT device : devices) {
      const bool software = hasExtension(eglQueryDeviceStringEXT(device, EGL_EXTENSIONS), "EGL_MESA_device_software");
      if (software != (pass == 1)) continue;
      if (tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr), out)) {
        platform = software ? "EGL device (Mesa software)" : "EGL device";
        return true;
      }
    }
  }
  return false;
}

bool trySurfaceless(EglAttempt& out, std::string& platform) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(client, "EGL_MESA_platform_surfaceless")) return false;
  if (!tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), out))
    return false;
  platform = "EGL surfaceless (Mesa)";
  return true;
}

void queryInfo(Info& info) {
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return std::string(s ? reinterpret_cast<const char*>(s) : "?");
  };
  info.vendor = str(GL_VENDOR);
  info.renderer = str(GL_RENDERER);
  info.version = str(GL_VERSION);
  info.glsl = str(GL_SHADING_LANGUAGE_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);
  for (GLuint i = 0; i < 3; ++i) glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, i, &info.maxComputeWorkGroupSize[i]);
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &info.maxComputeWorkGroupInvocations);
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &info.maxComputeSharedMemory);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info.maxTextureSize);
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info.max3DTextureSize);
  glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &info.maxTessellationLevel);
  glGetIntegerv(GL_MAX_PATCH_VERTICES, &info.maxPatchVertices);
}

}  // namespace

bool Info::software() const {
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
    if (renderer.find(name) != std::string::npos) return true;
  return false;
}

std::unique_ptr<Context> Context::headless() {
  const char* force = std::getenv("ISOATLAS_EGL");
  const std::string mode = force ? force : "";
  if (!mode.empty() && mode != "device" && mode != "surfaceless")
    throw Error("ISOATLAS_EGL=" + mode + " (expected device or surfaceless)");
  EglAttempt attempt;
  std::string platform;
  const bool ok = (mode != "surfaceless" && tryDevices(attempt, platform)) ||
                  (mode != "device" && trySurfaceless(attempt, platform));
  if (!ok)
    throw Error("no OpenGL 4.5 context: EGL found neither a GPU device nor Mesa's surfaceless platform "
                "(install libegl-mesa0 and libgl1-mesa-dri, or use --backend cpu)",
                ErrorKind::Failure);
  std::unique_ptr<Context> ctx(new Context);
  ctx->display_ = attempt.display;
  ctx->context_ = attempt.context;
  ctx->finishSetup(platform);
  return ctx;
}

void Context::finishSetup(const std::string& platform) {
  t_current = this;
  queryInfo(info_);
  info_.platform = platform;
  if (epoxy_gl_version() < 45)
    throw Error("OpenGL 4.5 core is needed; this driver gives " + info_.version + " (" + info_.renderer + ")",
                ErrorKind::Failure);
  ++g_made;
  serial_ = ++g_serials;
#ifndef NDEBUG
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(onDebugMessage, nullptr);
  enableDriverNotes(true);
#else
  enableDriverNotes(false);  // ISOATLAS_GL_PROFILE=1: the driver's notes (stage_profile.h); else nothing
#endif
  if (info_.software()) logInfo("gl: no GPU found, running on " + info_.renderer + " (software; slow but exact)");
}

bool Context::tryMakeCurrent() {
  if (window_) windowSystem_->makeCurrent(window_);
  else if (eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE, static_cast<EGLContext>(context_)) != EGL_TRUE)
    return false;
  if (!isCurrent()) return false;
  t_current = this;
  return true;
}

void Context::makeCurrent() {
  // A context is current on one thread at a time: eglMakeCurrent refuses it (EGL_BAD_ACCESS) on
  // another while it is current where it was made, and recording it as current anyway let GL calls
  // run on no context at all.
  if (!tryMakeCurrent())
    throw Error("the OpenGL context could not be made current on this thread (it is current on another one: "
                "release it there first, or make a context for this thread)",
                ErrorKind::Failure);
}

void Context::releaseCurrent() {
  if (window_) windowSystem_->makeCurrent(nullptr);
  else eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (t_current == this) t_current = nullptr;
}

bool Context::isCurrent() const {
  if (window_) return windowSystem_->current() == window_;
  return eglGetCurrentContext() == static_cast<EGLContext>(context_);
}

Context& Context::current() {
  if (!t_current || !t_current->isCurrent())
    throw Error("no OpenGL context is current: make one (gl::Context::headless() or window()) before any GPU work",
                ErrorKind::Failure);
  return *t_current;
}

int Context::made() { return g_made; }

bool Context::isCurrentSerial(std::uint64_t serial) {
  return serial != 0 && t_current && t_current->serial_ == serial && t_current->isCurrent();
}

const Program& Context::program(const ProgramSource& source) {
  const std::string key = source.key();
  if (auto it = programs_.find(key); it != programs_.end()) return it->second;
  if (!isCurrent()) throw Error("compiling " + source.paths.at(0) + ": its GL context is not current", ErrorKind::Failure);
  Program compiled(source);
  ++programsCompiled_;
  return programs_.emplace(key, std::move(compiled)).first->second;
}

Context::~Context() {
  // The cached programs go first, while this context is current; the context that was current
  // before (another one) is current again afterwards.
  Context* previous = t_current != this && t_current && t_current->isCurrent() ? t_current : nullptr;
  tryMakeCurrent();  // no throw from a destructor: where it cannot be made current, its programs leak with it
  programs_.clear();
  t_current = nullptr;
  if (window_) {
    // No glfwTerminate, for the same reason as no eglTerminate below: it unloads the GL driver.
    windowSystem_->destroy(window_);
  } else if (display_) {
    eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(static_cast<EGLDisplay>(display_), static_cast<EGLContext>(context_));
    // No eglTerminate: it unloads the driver, which leak checkers then cannot name. The display is
    // shared by every context of the process and ends with it.
  }
  if (previous) previous->tryMakeCurrent();
}

GLsizei glSize(std::uint64_t n, const char* what) {
  constexpr std::uint64_t kLargest = 2147483647;
  if (n > kLargest)
    throw Error(std::string(what) + ": " + std::to_string(n) + " is more than OpenGL takes in one call (2^31 - 1)", ErrorKind::Failure);
  return GLsizei(n);
}

void checkErrors(const char* where) {
  std::string message;
  if (GLenum e = glGetError(); e != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", e);
    message = std::string("GL error ") + code;
  }
  if (!g_debugError.empty()) {
    message = message.empty() ? g_debugError : message + ": " + g_debugError;
    g_debugError.clear();
  }
  while (glGetError() != GL_NO_ERROR) {
  }
  if (!message.empty()) throw Error(std::string(where) + ": " + message, ErrorKind::Failure);
}

}  // namespace isoatlas::gl
