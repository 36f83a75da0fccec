#include "app/options.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/progress.h"

namespace isoatlas::app {

std::array<int, 2> parseSize(const std::string& text) {
  const std::vector<double> v = parseNumbers(text, "--size", "W,H");
  require(v.size() == 2 && v[0] == std::floor(v[0]) && v[1] == std::floor(v[1]) && v[0] >= 1 && v[1] >= 1 && v[0] <= 8192 && v[1] <= 8192,
          "--size " + text + ": expected W,H, whole pixels from 1 to 8192");
  return {int(v[0]), int(v[1])};
}

Ball parseBall(const std::string& text, const std::string& option, double defaultRadius) {
  const std::vector<double> numbers = parseNumbers(text, option, "X,Y,Z or X,Y,Z,R");
  if (numbers.size() != 3 && numbers.size() != 4) throw Error(option + " " + text + ": expected X,Y,Z or X,Y,Z,R");
  const double radius = numbers.size() == 4 ? numbers[3] : defaultRadius;
  if (radius <= 0) throw Error(option + " " + text + ": the radius must be > 0");
  return {{numbers[0], numbers[1], numbers[2]}, radius};
}

void requireInside(const Volume& v, const Vec3& p, const std::string& what) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < 0 || p[a] > double(v.dims[a] - 1))
      throw Error(what + " (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                  ") lies outside the volume, whose voxel indices run 0.." + std::to_string(v.dims[0] - 1) + ", 0.." +
                  std::to_string(v.dims[1] - 1) + ", 0.." + std::to_string(v.dims[2] - 1));
}

gl::Context& Gpu::needGl() {
  if (!context) context = gl::Context::headless();
  if (!context->isCurrent()) context->makeCurrent();
  return *context;
}

Gpu chooseBackend(const std::string& choice) {
  Gpu gpu;
  if (choice == "cpu") return gpu;
  if (choice != "gpu" && choice != "auto") throw Error("--backend " + choice + ": expected gpu, cpu or auto");
  try {
    const gl::Info& info = gpu.needGl().info();
    if (choice == "auto" && info.software()) {
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

}  // namespace isoatlas::app
