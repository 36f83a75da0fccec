#include "app/options.h"

#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/progress.h"

namespace isoatlas::app {

std::vector<double> parseNumbers(const std::string& text, const std::string& option, const char* expected) {
  std::vector<double> numbers;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(v))
      throw Error(option + " " + text + ": \"" + part + "\" is not a number (expected " + expected + ")");
    numbers.push_back(v);
  }
  return numbers;
}

Vec3 parsePoint(const std::string& text, const std::string& option) {
  const std::vector<double> numbers = parseNumbers(text, option, "X,Y,Z");
  if (numbers.size() != 3) throw Error(option + " " + text + ": expected X,Y,Z");
  return {numbers[0], numbers[1], numbers[2]};
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
