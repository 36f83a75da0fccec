// Context: one OpenGL 4.5 core context, made current on the calling thread.
//   headless(): EGL, on a real GPU through EGL_EXT_platform_device, else Mesa's surfaceless platform
//               (llvmpipe on a machine without a GPU). There is no default framebuffer: bind an FBO
//               before drawing. ISOATLAS_EGL=device|surfaceless forces one platform.
//   window():   a GLFW window (needs a display; Xvfb in tests). Defined in window_context.cpp, in its
//               own library (isoatlas_gl_window): only what opens a window links GLFW, so the
//               Python module and the command's headless paths do not.
// The caller makes the context and keeps it current; GPU algorithms take the current one
// (Context::current(), checked) and never open their own, as OpenSubdiv's GL evaluators do. A process
// makes one unless it asks for more. GL objects made in a context must be destroyed before it, while
// it is current.
// In debug builds GL debug output is on and errors it reports are thrown by checkErrors().
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "core/gl/program.h"

struct GLFWwindow;

namespace isoatlas::gl {

struct Info {
  std::string vendor, renderer, version, glsl, platform;
  int major = 0, minor = 0;
  int maxComputeWorkGroupSize[3] = {0, 0, 0};
  int maxComputeWorkGroupInvocations = 0;
  int maxComputeSharedMemory = 0;
  int maxTextureSize = 0, max3DTextureSize = 0;
  int maxTessellationLevel = 0, maxPatchVertices = 0;
  bool software() const;  // llvmpipe, softpipe, swrast
};

class Context {
public:
  static std::unique_ptr<Context> headless();
  static std::unique_ptr<Context> window(int width, int height, const std::string& title, bool visible = true);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Throws Error (Failure) where it cannot be made current here (it is current on another thread).
  void makeCurrent();
  // Leaves no context current on this thread (before handing a window's context to another thread).
  void releaseCurrent();
  bool isCurrent() const;  // asks EGL or GLFW, not a flag of ours
  // The context of ours current on this thread; throws Error (Failure) when there is none.
  static Context& current();
  // Contexts this process has made so far (reported as gl_contexts).
  static int made();
  // This context's number in the process (1, 2, ...; never reused), by which GL objects name the
  // context they were made in: a pointer could outlive the context or name a newer one.
  std::uint64_t serial() const { return serial_; }
  // Whether the context numbered `serial` is current on this thread (false once it is destroyed).
  static bool isCurrentSerial(std::uint64_t serial);

  // The program compiled from `source` in this context: compiled on the first request, the same
  // object afterwards. Lives as long as the context.
  const Program& program(const ProgramSource& source);
  const Program& compute(const EmbeddedShader* files, const std::string& path, const Defines& defines = {}) {
    return program({files, {path}, defines, {}});
  }
  int programsCompiled() const { return programsCompiled_; }

  const Info& info() const { return info_; }
  GLFWwindow* glfwWindow() const { return window_; }

private:
  bool tryMakeCurrent();  // makeCurrent's work: false where EGL refuses (or it is not current after)
  // What a window's context asks of its window system, given by window(), so that this library
  // calls no GLFW function itself.
  struct WindowSystem {
    void (*makeCurrent)(GLFWwindow*);
    GLFWwindow* (*current)();
    void (*destroy)(GLFWwindow*);
  };
  Context() = default;
  void finishSetup(const std::string& platform);
  Info info_;
  std::map<std::string, Program> programs_;
  int programsCompiled_ = 0;
  std::uint64_t serial_ = 0;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  GLFWwindow* window_ = nullptr;
  const WindowSystem* windowSystem_ = nullptr;  // with window_
};

// Throws isoatlas::Error (Failure) if GL reported an error since the last call: glGetError and,
// in debug builds, debug-output messages of type error.
void checkErrors(const char* where);

// A count or byte size for a GL call that takes a 32-bit signed one (GLsizei): throws Error
// (Failure) naming `what` and the size where it passes 2^31 - 1, where the cast would wrap negative.
GLsizei glSize(std::uint64_t n, const char* what);

}  // namespace isoatlas::gl
