// bench/render: the tessellated atlas beside OpenSubdiv, in the same run and the same GL context.
//   Speed: the grid scene at 1920 x 1080 (4 x 4 instances here, 10 x 10 with ISOATLAS_BENCH_GPU=1 on
//   a real GPU), our cascade (CPU level by distance, GPU segments set to draw as many triangles as
//   the peer, within 2 %) against OpenSubdiv's own adaptive tessellation of the same base mesh (Far
//   patch tables, Osd's GLSL patch shaders, Gregory-basis end caps) at the uniform level nearest our
//   cascade at 8-pixel segments: median frame time over five frames after the first, and triangles
//   per second of GPU time; each through its fastest pipeline (OpenSubdiv's evaluation straight to
//   the fragments, ours through a geometry stage), and both through the geometry stage.
//   Accuracy at equal triangles: PSNR against the dense mesh (CGAL's Hausdorff distance) of the
//   atlas at levels 4, 6, 8, of the smooth mode (OpenSubdiv's limit surface with the atlas's detail
//   along its normal) and of the limit surface alone, 8 T^2 triangles a tile at T = 2, 4, 8; a
//   picture of the three at level 6 (bench/render_modes.png).
//   Watertightness: the share of edges matched by a neighbour's after welding the captured
//   triangles by exact position (1: no crack).
#include <cstdlib>
#include <functional>
#include <filesystem>

#include "pipeline/model_building.h"
#include "core/distance/mesh_distance.h"
#include "bench/bench_util.h"
#include "core/gl/context.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "core/text.h"
#include "render/scene.h"
#include "render/smooth_render.h"

using namespace isoatlas;

namespace {

std::string device;  // the GL renderer, named with every figure

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Edges matched by one running the other way, over all edges, after welding by exact position.
double watertight(const Mesh& captured) {
  const Mesh welded = weldIdenticalPositions(captured);
  const std::size_t edges = directedEdgeBalance(welded).size();
  return double(edges - unbalancedEdges(welded)) / double(std::max<std::size_t>(edges, 1));
}

// Median frame time (ms), median GPU time (ms) and triangles of five frames after a first one.
struct Timed {
  double frameMs = 0, gpuMs = 0;
  std::uint64_t triangles = 0;
};
Timed timed(const std::function<render::FrameReport()>& frame) {
  std::vector<double> ms, gpu;
  std::uint64_t triangles = 0;
  for (int k = 0; k < 6; ++k) {
    const render::FrameReport f = frame();
    if (k == 0) continue;  // programs compiled, patch lists made and sent
    ms.push_back(f.ms), gpu.push_back(f.gpu.gpuMs), triangles = f.gpu.triangles;
  }
  return {median(ms), median(gpu), triangles};
}

void speed(const std::string& name, const atlas::Model& model, int grid) {
  render::Scene scene({&model});
  scene.grid(grid);
  const render::Camera camera = scene.defaultCamera(1920, 1080);
  const gl::Framebuffer target(camera.width, camera.height);
  const render::AtlasRenderer renderer;
  const render::CpuRefinement cpu{render::CpuRefinement::Mode::Level, 6};
  auto ours = [&](double pixels) {
    return render::drawFrame(scene, renderer, cpu, {render::GpuRefinement::Mode::Pixels, 0, pixels}, camera, {}, target);
  };
  // OpenSubdiv's uniform level nearest our cascade at 8-pixel segments; then our segment length
  // set (bisection) so that we draw as many triangles as it does.
  const std::uint64_t first = ours(8).gpu.triangles;
  const render::SmoothSurface smooth(model, scene.textures(0));
  const double perLevel = 8.0 * double(smooth.baseFaces() * scene.instances().size());
  const int level = std::clamp(int(std::lround(std::sqrt(double(first) / perLevel) / 2)) * 2, 2, 32);
  const double wanted = perLevel * level * level;
  double low = 1, high = 64, pixels = 8;
  for (int k = 0; k < 10; ++k) {
    pixels = std::sqrt(low * high);
    const double got = double(ours(pixels).gpu.triangles);
    if (std::abs(got / wanted - 1) < 0.02) break;
    (got > wanted ? low : high) = pixels;
  }
  const Timed a = timed([&] { return ours(pixels); });
  auto theirs = [&](const render::DrawStyle& style) {
    return timed([&] { return render::drawSmoothFrame(scene, smooth, level, false, camera, style, target); });
  };
  const Timed b = theirs({});
  // The same pipeline for both: OpenSubdiv's evaluation through our geometry stage, as ours always
  // goes (with the wireframe, which both then draw).
  render::DrawStyle wire;
  wire.wireframe = true;
  const Timed aWire = timed([&] { return render::drawFrame(scene, renderer, cpu, {render::GpuRefinement::Mode::Pixels, 0, pixels}, camera, wire, target); });
  const Timed bWire = theirs(wire);
  char segments[64];
  std::snprintf(segments, sizeof segments, "%.1f", pixels);
  const std::string caseName = name + ", grid " + std::to_string(grid) + "x" + std::to_string(grid) + " at 1920x1080";
  const std::string peer = "OpenSubdiv adaptive tessellation of the base mesh, level " + std::to_string(level);
  std::fprintf(stderr, "bench render: %s: ours (GPU segments of %s pixels) %llu triangles, %.1f ms a frame; OpenSubdiv %llu triangles, %.1f ms\n",
               caseName.c_str(), segments, (unsigned long long)a.triangles, a.frameMs, (unsigned long long)b.triangles, b.frameMs);
  bench::report("render", caseName, "frame ms (ours: CPU + GPU)", a.frameMs, peer, b.frameMs, true, device);
  bench::report("render", caseName, "triangles per frame", double(a.triangles), peer, double(b.triangles), false, device);
  bench::report("render", caseName, "million triangles per GPU second", double(a.triangles) / a.gpuMs / 1000, peer,
                double(b.triangles) / b.gpuMs / 1000, false, device);
  bench::report("render", caseName, "frame ms, both through the geometry stage (wireframe)", aWire.frameMs, peer, bWire.frameMs, true, device);
}

// Columns side by side, on white.
Image sideBySide(const std::vector<Image>& images) {
  int width = 0, height = 0;
  for (const Image& i : images) width += i.width, height = std::max(height, i.height);
  Image out(width, height, 3);
  std::fill(out.pixels.begin(), out.pixels.end(), 255);
  int x0 = 0;
  for (const Image& i : images) {
    for (int y = 0; y < i.height; ++y)
      for (int x = 0; x < i.width; ++x)
        for (int c = 0; c < 3; ++c) out.at(x0 + x, y)[c] = i.at(x, y)[c];
    x0 += i.width;
  }
  return out;
}

void accuracy(const std::string& name, const atlas::Model& model, const Mesh& dense) {
  render::Scene scene({&model});
  const render::Camera camera = scene.defaultCamera(480, 360);
  const render::AtlasRenderer renderer;
  const render::SmoothSurface smooth(model, scene.textures(0));
  const double diagonal = boundingBox(dense.positions).diagonal();
  const gl::Framebuffer target(camera.width, camera.height);
  std::vector<Image> pictures;
  for (const int level : {4, 6, 8}) {
    const int t = 1 << (level / 2 - 1);  // 8 T^2 = 2 * 4^(level / 2): equal triangles a tile
    scene.refine({render::CpuRefinement::Mode::Level, level}, camera);
    const Mesh atlasMesh = renderer.capture(scene.items(), camera, scene.bounds(), {render::GpuRefinement::Mode::Level, 0});
    const Mesh detailed = smooth.capture({{0, 0, 0}}, camera, scene.bounds(), t, true);
    const Mesh limit = smooth.capture({{0, 0, 0}}, camera, scene.bounds(), t, false);
    const double psnrAtlas = psnrDb(diagonal, hausdorffDistance(atlasMesh, dense).symmetric());
    const double psnrDetailed = psnrDb(diagonal, hausdorffDistance(detailed, dense).symmetric());
    const double psnrLimit = psnrDb(diagonal, hausdorffDistance(limit, dense).symmetric());
    const std::string caseName = name + ", " + std::to_string(atlasMesh.faceCount()) + " triangles";
    std::fprintf(stderr, "bench render: %s: PSNR atlas level %d %.1f dB, smooth T %d with detail %.1f dB, limit alone %.1f dB (%zu, %zu triangles)\n",
                 caseName.c_str(), level, psnrAtlas, t, psnrDetailed, psnrLimit, detailed.faceCount(), limit.faceCount());
    bench::report("render", caseName, "PSNR dB, atlas at level " + std::to_string(level), psnrAtlas,
                  "OpenSubdiv limit surface of the base mesh, T " + std::to_string(t), psnrLimit, false, device);
    bench::report("render", caseName, "PSNR dB, smooth mode (limit + the atlas's detail), T " + std::to_string(t), psnrDetailed,
                  "OpenSubdiv limit surface of the base mesh, T " + std::to_string(t), psnrLimit, false, device);
    bench::report("render", caseName, "watertight edges after exact weld (atlas at level " + std::to_string(level) + ")",
                  watertight(atlasMesh), "OpenSubdiv limit surface, T " + std::to_string(t), watertight(limit), false, device);
    if (level == 6) {
      auto labelled = [&](const std::string& label, double psnr) {
        Image picture = target.readImage();
        char text[160];
        std::snprintf(text, sizeof text, "%s: %.1f dB", label.c_str(), psnr);
        drawText(picture, 12, 10, text, 18, {40, 40, 40});
        pictures.push_back(std::move(picture));
      };
      renderer.draw(scene.items(), camera, scene.bounds(), {render::GpuRefinement::Mode::Level, 0}, {}, target);
      labelled("atlas, level 6", psnrAtlas);
      smooth.draw({{0, 0, 0}}, camera, scene.bounds(), t, true, {}, target);
      labelled("smooth + detail, T 4", psnrDetailed);
      smooth.draw({{0, 0, 0}}, camera, scene.bounds(), t, false, {}, target);
      labelled("OpenSubdiv limit, T 4", psnrLimit);
    }
  }
  writePng(std::filesystem::path(ISOATLAS_BENCH_DIR).append("render_modes.png").string(), sideBySide(pictures));
}

}  // namespace

// bench_render [DATA [MESH]]: MESH in DATA/meshes (default bunny00).
int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data", name = argc > 2 ? argv[2] : "bunny00";
  const auto context = gl::Context::headless();
  device = context->info().renderer + " (" + bench::machineName() + ")";
  const Mesh dense = pipeline::prepareModelInput(readMesh(data + "/meshes/" + name + ".off"));
  nlohmann::json figures;
  const atlas::Model model = pipeline::buildModel(dense, {.hausdorff = false}, figures);
  const bool gpu = std::getenv("ISOATLAS_BENCH_GPU") && std::string(std::getenv("ISOATLAS_BENCH_GPU")) == "1";
  speed(name, model, gpu ? 10 : 4);
  accuracy(name, model, dense);
  return 0;
}
