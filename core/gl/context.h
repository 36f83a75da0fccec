// Context: one OpenGL 4.5 core context, made current on the calling thread.
//   headless(): EGL, on a real GPU through EGL_EXT_platform_device, else Mesa's surfaceless platform
//               (llvmpipe on a machine without a GPU). There is no default framebuffer: bind an FBO
//               before drawing. ISOATLAS_EGL=device|surfaceless forces one platform.
//   window():   a GLFW window (needs a display; Xvfb in tests).
// In debug builds GL debug output is on and errors it reports are thrown by checkErrors().
#pragma once
#include <memory>
#include <string>

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

  void makeCurrent();
  const Info& info() const { return info_; }
  GLFWwindow* glfwWindow() const { return window_; }

private:
  Context() = default;
  void finishSetup(const std::string& platform);
  Info info_;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  GLFWwindow* window_ = nullptr;
};

// Throws isoatlas::Error (Failure) if GL reported an error since the last call: glGetError and,
// in debug builds, debug-output messages of type error.
void checkErrors(const char* where);

}  // namespace isoatlas::gl
