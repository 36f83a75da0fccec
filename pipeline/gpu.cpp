#include "pipeline/gpu.h"

#include "core/error.h"
#include "core/progress.h"

namespace isoatlas::pipeline {

gl::Context& Gpu::needGl() {
  if (!context) context = gl::Context::headless();
  if (!context->isCurrent()) context->makeCurrent();
  return *context;
}

Gpu chooseBackend(const std::string& choice) {
  Gpu gpu;
  levelset::requireBackendChoice(choice);
  if (choice == "cpu") return gpu;
  try {
    const gl::Info& info = gpu.needGl().info();
    if (levelset::backendFor(choice, info.software()) == levelset::Backend::Cpu) {
      logInfo("no GPU: using the CPU backend (--backend gpu runs the GPU path on " + info.renderer + ")");
      return gpu;
    }
    gpu.backend = levelset::Backend::Gpu;
    gpu.renderer = info.renderer;
    return gpu;
  } catch (const Error& e) {
    if (choice == "gpu") throw Error(std::string(e.what()) + "; --backend cpu runs without a GPU", ErrorKind::Failure);
    logInfo(std::string("no OpenGL 4.5: using the CPU backend (") + e.what() + ")");
    return gpu;
  }
}

}  // namespace isoatlas::pipeline
