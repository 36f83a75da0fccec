#include "app/run_model_views.h"

#include <algorithm>
#include <cstdio>

#include "atlas/reconstruct.h"
#include "core/gl/resources.h"
#include "core/image.h"
#include "render/scene.h"

namespace isoatlas::app {

std::string renderModelViews(const atlas::Model& model, pipeline::RunProducts& products, nlohmann::json& r) {
  const render::AtlasRenderer renderer;
  render::Scene scene({&model});
  const render::Camera camera = render::Camera::framing(scene.bounds(), 800, 600, {1, 0, 0});
  const gl::Framebuffer target(camera.width, camera.height);
  const int top = atlas::maxLevel(model.chartSize);
  const render::GpuRefinement byView{render::GpuRefinement::Mode::Pixels, 0, 16};
  auto frame = [&](const render::CpuRefinement& cpu, const render::GpuRefinement& gpu, const render::DrawStyle& style,
                   const render::Camera& c, const std::string& file, const std::string& what) {
    const render::FrameReport f = render::drawFrame(scene, renderer, cpu, gpu, c, style, target);
    writePng(products.add(file, what, true), target.readImage());
    r["views"].push_back({{"file", file}, {"patches", f.gpu.patches}, {"triangles", f.gpu.triangles}, {"cpu_ms", f.cpu.ms},
                          {"gpu_ms", f.gpu.gpuMs}, {"frame_ms", f.ms}});
  };
  // The finest through the cascade: the CPU at a middle level, the GPU's halvings (two levels each) above it.
  const int middle = std::min(top / 2 / 2 * 2, 4), halvings = (top - middle) / 2;
  for (const int level : {2, middle, top}) {
    const int cpuLevel = level == top ? top - 2 * halvings : level;
    const render::GpuRefinement gpu{render::GpuRefinement::Mode::Level, level == top ? halvings : 0};
    frame({render::CpuRefinement::Mode::Level, cpuLevel}, gpu, {}, camera, "render_level" + std::to_string(level) + ".png",
          "the model tessellated at level " + std::to_string(level) + " (isoatlas render --cpu-level " + std::to_string(cpuLevel) +
              " --gpu-level " + std::to_string(gpu.halvings) + ")");
  }
  render::DrawStyle wire;
  wire.wireframe = true;
  const render::CpuRefinement byError{render::CpuRefinement::Mode::Pixels, 0, 3};
  frame(byError, byView, wire, camera, "render_wire.png",
        "the cascade: the CPU splits to 3 pixels of error, the GPU to 16-pixel segments; tile borders brown, tile interiors blue");
  const int turns = 8;
  render::Camera small = camera;
  small.width = 320, small.height = 240;
  const gl::Framebuffer smallTarget(small.width, small.height);
  for (int k = 0; k < turns; ++k) {
    char file[32];
    std::snprintf(file, sizeof file, "turntable_%03d.png", k);
    const render::Camera c = small.turned(2 * 3.14159265358979 * k / turns);
    render::drawFrame(scene, renderer, byError, byView, c, {}, smallTarget);
    writePng(products.add(file, "turntable frame " + std::to_string(k + 1) + " of " + std::to_string(turns), k == 0), smallTarget.readImage());
  }
  return "levels 2, " + std::to_string(middle) + ", " + std::to_string(top) + ", the wireframe and " +
         std::to_string(turns) + " turntable frames: render_*.png, turntable_*.png";
}

}  // namespace isoatlas::app
