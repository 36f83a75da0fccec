// isoatlas render: a model (or a grid of models) drawn headless through the cascade: the CPU's
// adaptive level, then GL tessellation of the atlas; PNG images, the GPU's triangles as a mesh, and
// the frame's figures.
#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

#include "app/command.h"
#include "pipeline/segmentation_views.h"
#include "edit/dvt/dvt_file.h"
#include "render/orbit.h"
#include "render/dvt_render.h"
#include "app/options.h"
#include "atlas/reconstruct.h"
#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "core/progress.h"
#include "render/scene.h"
#include "render/smooth_render.h"

namespace isoatlas::app {
namespace {

// What the GPU made, welded by exact position, as the crack tests see it: closed or not, edges of one
// triangle, edges of three or more, and edges not run once each way (directedEdgeBalance). The atlas's
// tessellation is closed on a closed model; the smooth mode's need not be, and the report says which.
nlohmann::json captureFigures(const Mesh& captured) {
  const MeshTopology t = analyzeTopology(captured);
  return {{"captured_vertices", captured.vertexCount()}, {"captured_triangles", captured.faceCount()},
          {"captured_closed", t.closed}, {"captured_boundary_edges", t.boundaryEdges},
          {"captured_non_manifold_edges", t.nonManifoldEdges}, {"captured_unbalanced_edges", unbalancedEdges(captured)}};
}

struct RenderOptions {
  std::vector<std::string> models;
  int cpuLevel = -1;
  double cpuError = 0, gpuPixels = 0;
  int gpuLevel = -1;
  std::string camera, size = "800,600", output, capture, scene;
  bool wire = false, chartColours = false;
  int turntable = 0, frames = 1;
  int smooth = 0;  // OpenSubdiv's tessellation level; 0: the atlas mode
  bool limitOnly = false;
};

render::Camera parseCamera(const std::string& text, int width, int height) {
  const std::vector<double> v = parseNumbers(text, "--camera", "EX,EY,EZ,TX,TY,TZ,FOV");
  require(v.size() == 7, "--camera " + text + ": expected EX,EY,EZ,TX,TY,TZ,FOV (eye, target, vertical field of view in degrees)");
  render::Camera c;
  c.eye = {v[0], v[1], v[2]};
  c.target = {v[3], v[4], v[5]};
  c.fovDegrees = v[6];
  c.width = width, c.height = height;
  c.check();
  return c;
}

// "grid:NxN" -> N
int parseGrid(const std::string& text) {
  int n = 0, m = 0;
  char tail = 0;
  require(std::sscanf(text.c_str(), "grid:%dx%d%c", &n, &m, &tail) == 2 && n == m && n >= 1 && n <= 64,
          "--scene " + text + ": expected grid:NxN with N from 1 to 64 (e.g. grid:10x10)");
  return n;
}

std::string framePath(const std::string& output, int frame, int frames) {
  if (frames <= 1) return output;
  const std::filesystem::path p(output);
  char number[16];
  std::snprintf(number, sizeof number, "_%03d", frame);
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The options checked before anything is read or a GL context made.
struct Plan {
  int width = 0, height = 0, grid = 0;
  render::CpuRefinement cpu;
  render::GpuRefinement gpu;
  std::optional<render::Camera> camera;
};
Plan plan(const RenderOptions& o) {
  require(o.output.ends_with(".png"), o.output + ": -o writes a .png");
  require(o.cpuLevel < 0 || o.cpuError == 0, "give --cpu-level or --cpu-error, not both");
  require(o.gpuLevel < 0 || o.gpuPixels == 0, "give --gpu-level or --gpu-pixels, not both");
  require(o.models.size() == 1 || !o.scene.empty(), "several models are drawn only in a --scene");
  require(o.smooth == 0 || o.models.size() == 1, "--smooth draws one model (in a --scene, its instances)");
  require(o.smooth > 0 || !o.limitOnly, "--limit-only goes with --smooth");
  Plan p;
  const auto size = parseSize(o.size);
  p.width = size[0], p.height = size[1];
  p.grid = o.scene.empty() ? 0 : parseGrid(o.scene);
  if (o.cpuLevel >= 0) p.cpu = {render::CpuRefinement::Mode::Level, o.cpuLevel};
  else if (o.cpuError > 0) p.cpu = {render::CpuRefinement::Mode::Pixels, 0, o.cpuError};
  if (o.gpuLevel >= 0) p.gpu = {render::GpuRefinement::Mode::Level, o.gpuLevel};
  else if (o.gpuPixels > 0) p.gpu = {render::GpuRefinement::Mode::Pixels, 0, o.gpuPixels};
  if (!o.camera.empty()) p.camera = parseCamera(o.camera, p.width, p.height);
  return p;
}

// What the frames measured, for the report.
struct FrameLog {
  std::vector<double> cpuMs, gpuMs, frameMs;
  std::vector<std::string> images;
  render::FrameReport last;
  std::size_t uploadBytes = 0, splits = 0, welds = 0;
  void add(const render::FrameReport& f) {
    last = f;
    cpuMs.push_back(f.cpu.ms), gpuMs.push_back(f.gpu.gpuMs), frameMs.push_back(f.ms);
    uploadBytes += f.cpu.uploadBytes, splits += f.cpu.splits, welds += f.cpu.welds;
  }
  void report(nlohmann::json& r) const {
    r["patches"] = last.gpu.patches;
    r["triangles"] = last.gpu.triangles;
    r["cpu_triangles"] = last.cpu.cpuFaces;
    r["cpu_ms"] = median(cpuMs);
    r["gpu_ms"] = median(gpuMs);
    r["frame_ms"] = median(frameMs);
    r["fps"] = 1000 / std::max(median(frameMs), 1e-9);
    r["triangles_per_second"] = double(last.gpu.triangles) * 1000 / std::max(median(gpuMs), 1e-9);
    r["upload_bytes"] = uploadBytes;  // patch lists, over all frames
    r["cpu_splits"] = splits;         // over all frames: --cpu-error carries each instance's mesh on
    r["cpu_welds"] = welds;
    r["frames"] = frameMs.size();
    r["images"] = images;
  }
};

int render(const RenderOptions& o, nlohmann::json& r) {
  const Plan p = plan(o);
  std::vector<atlas::Model> models;
  for (const std::string& path : o.models) {
    models.push_back(atlas::readModel(path));
    const int top = atlas::maxLevel(models.back().chartSize);
    const std::string charts = " for " + path + " (charts of " + std::to_string(models.back().chartSize) + " texels)";
    require(o.cpuLevel <= top, "--cpu-level must lie between 0 and " + std::to_string(top) + charts);
    // A halving past the chart's texels would draw nothing finer: refused rather than clamped.
    require(o.gpuLevel < 0 || std::max(o.cpuLevel, 0) + 2 * o.gpuLevel <= top,
            "--gpu-level " + std::to_string(o.gpuLevel) + ": with --cpu-level " + std::to_string(std::max(o.cpuLevel, 0)) +
                " this asks for level " + std::to_string(std::max(o.cpuLevel, 0) + 2 * o.gpuLevel) + ", past the finest, " +
                std::to_string(top) + charts);
  }
  pipeline::Gpu gpu;  // the process's one context
  gpu.needGl();
  std::vector<const atlas::Model*> pointers;
  for (const atlas::Model& m : models) pointers.push_back(&m);
  render::Scene scene(pointers);
  if (p.grid) scene.grid(p.grid);
  const render::Camera first = p.camera ? *p.camera : scene.defaultCamera(p.width, p.height);
  render::DrawStyle style;
  style.wireframe = o.wire;
  style.colourByChart = o.chartColours;

  const render::AtlasRenderer renderer;
  std::unique_ptr<render::SmoothSurface> smooth;
  if (o.smooth) smooth = std::make_unique<render::SmoothSurface>(models.front(), scene.textures(0));
  const gl::Framebuffer target(p.width, p.height);
  const int images = std::max(o.turntable, 1), frames = std::max(images, o.frames);
  FrameLog log;
  Progress progress("render", std::size_t(frames));
  for (int f = 0; f < frames; ++f) {
    const render::Camera camera = o.turntable > 0 ? first.turned(2 * 3.14159265358979 * (f % images) / images) : first;
    log.add(smooth ? render::drawSmoothFrame(scene, *smooth, o.smooth, !o.limitOnly, camera, style, target)
                   : render::drawFrame(scene, renderer, p.cpu, p.gpu, camera, style, target));
    if (f < images) {
      log.images.push_back(framePath(o.output, f, images));
      writePng(log.images.back(), target.readImage());
    }
    progress.update(std::uint64_t(f + 1));
  }
  progress.finish();
  if (!o.capture.empty()) {
    scene.refine(p.cpu, first);
    const Mesh captured = weldIdenticalPositions(smooth ? smooth->capture(scene.offsets(), first, scene.bounds(), o.smooth, !o.limitOnly)
                                                        : renderer.capture(scene.items(), first, scene.bounds(), p.gpu));
    writeMesh(o.capture, captured);
    r.update(captureFigures(captured));
  }
  log.report(r);
  r["renderer"] = gpu.needGl().info().renderer;
  r["mode"] = o.smooth ? (o.limitOnly ? "smooth limit (OpenSubdiv)" : "smooth with the atlas's detail (OpenSubdiv)") : "atlas";
  r["instances"] = scene.instances().size();
  if (p.cpu.mode == render::CpuRefinement::Mode::Level) r["cpu_levels"] = {log.last.cpu.minLevel, log.last.cpu.maxLevel};
  r["size"] = {p.width, p.height};
  logInfo("render: " + std::to_string(log.last.gpu.patches) + " patches, " + std::to_string(log.last.gpu.triangles) +
          " triangles, frame " + std::to_string(median(log.frameMs)) + " ms (CPU " + std::to_string(median(log.cpuMs)) +
          " ms, GPU " + std::to_string(median(log.gpuMs)) + " ms) on " + r["renderer"].get<std::string>());
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("render", "draw a model headless (CPU level, then GPU tessellation of its atlas), or a volume and "
                                           "its segmentation as the view window shows them, to PNG");
  auto o = std::make_shared<RenderOptions>();
  auto seg = std::make_shared<pipeline::SegmentationViewRequest>();
  sub->add_option("model", o->models, "the .isoatlas model (several with --scene: placed in turn), a volume, or a volume tree (.dvt)")
      ->required();
  sub->add_option("--segmentation", seg->segmentation, "a volume: its segmentation (mask or phi, the volume's grid), drawn as the window does");
  sub->add_option("--view", seg->view, "a volume: slices (default: the three planes, the contour) or volume (ray cast from the "
                                       "level set's pages); a tree (.dvt): raycast (default) or cubes");
  auto at = std::make_shared<std::string>();
  sub->add_option("--at", *at, "a volume: X,Y,Z, the slice point (world mm); default the volume's centre");
  sub->add_option("--clip", seg->clip, "a volume's --view volume: cut away the side +x, -x, +y, -y, +z or -z of the slice point")
      ->capture_default_str();
  sub->add_flag("--inside-only", seg->insideOnly, "a volume's --view volume: the scan only inside the segmentation");
  sub->add_option("--opacity", seg->opacity, "a volume's --view volume: opacity per voxel at the window's top")
      ->capture_default_str()
      ->check(inRange(1e-4, 1));
  auto* level = sub->add_option("--cpu-level", o->cpuLevel, "CPU level L everywhere (0: the base mesh's tiles; in a grid: for the nearest, lower with distance)")
                    ->check(inRange(0, kMaxLevel));
  sub->add_option("--cpu-error", o->cpuError, "CPU: split where the surface moves more than E pixels (default 2)")
      ->excludes(level)
      ->check(inRange(0.01, 1e4));
  auto* halvings = sub->add_option("--gpu-level", o->gpuLevel, "GPU: T more halvings of every CPU edge (two levels each; 0: none), up to the chart's texels")
                       ->check(inRange(0, kMaxLevel / 2));
  sub->add_option("--gpu-pixels", o->gpuPixels, "GPU: segments of about P pixels on the screen (default 8)")
      ->excludes(halvings)
      ->check(inRange(0.1, 1e4));
  sub->add_option("--camera", o->camera, "EX,EY,EZ,TX,TY,TZ,FOV: eye, target (world mm), vertical field of view (degrees); default: the whole model");
  sub->add_option("--size", o->size, "W,H: image size in pixels")->capture_default_str();
  sub->add_flag("--wire", o->wire, "a wireframe over the surface: tile borders brown, inside the tiles blue");
  sub->add_flag("--chart-colours", o->chartColours, "colour each tile's chart apart");
  sub->add_option("--turntable", o->turntable, "N frames around the vertical axis: IMAGE_000.png ... (0: one still image)")
      ->capture_default_str()
      ->check(inRange(0, 3600));
  sub->add_option("--frames", o->frames, "draw this many frames and report the median times")->capture_default_str()->check(inRange(1, 1000));
  sub->add_option("--scene", o->scene, "grid:NxN: N x N instances, CPU level by distance, GPU level by view");
  sub->add_option("--smooth", o->smooth, "smooth mode: the base mesh as a Catmull-Clark cage, OpenSubdiv's limit surface at "
                                        "tessellation level T with the atlas's detail along its normal (0: the atlas mode, not smooth)")
      ->capture_default_str()
      ->check(inRange(0, 32));
  sub->add_flag("--limit-only", o->limitOnly, "with --smooth: OpenSubdiv's limit surface alone, no detail");
  sub->add_option("-o,--output", o->output, "the image (.png)")->required()->check(outputFile());
  sub->add_option("--capture", o->capture, "the triangles the GPU made (transform feedback), welded, world mm (.ply, .obj, .off, .stl)")->check(outputFile());
  bindAction(*sub, [o, seg, at](nlohmann::json& r) {
    if (endsWith(o->models.front(), ".dvt")) {  // a volume tree, as the window's tree view draws it
      require(o->models.size() == 1, "render draws one tree");
      require(o->output.ends_with(".png"), o->output + ": -o writes a .png");
      require(seg->view.empty() || seg->view == "raycast" || seg->view == "cubes", "--view " + seg->view + ": expected raycast or cubes for a tree");
      const edit::dvt::VolumeTree tree = edit::dvt::readDvt(o->models.front());
      const auto [width, height] = parseSize(o->size);
      pipeline::Gpu gpu;
      gpu.needGl();
      const render::Camera camera = o->camera.empty() ? render::Orbit{}.camera(render::insideBounds(tree), width, height)
                                                      : parseCamera(o->camera, width, height);
      writePng(o->output, render::renderTree(tree, {.camera = camera, .mode = seg->view == "cubes" ? render::DvtRenderMode::Cubes
                                                                                                 : render::DvtRenderMode::RayCast}));
      r["images"] = {o->output};
      r["nodes"] = tree.nodeCount();
      return 0;
    }
    if (!endsWith(o->models.front(), ".isoatlas")) {  // a volume: the window's segmentation views
      require(o->models.size() == 1, "render draws one volume");
      require(o->output.ends_with(".png"), o->output + ": -o writes a .png");
      pipeline::SegmentationViewRequest request = *seg;
      request.volume = o->models.front();
      if (!at->empty()) request.at = parsePoint(*at, "--at");
      const auto [width, height] = parseSize(o->size);
      request.width = width, request.height = height;
      if (!o->camera.empty()) request.camera = parseCamera(o->camera, width, height);
      writePng(o->output, pipeline::renderSegmentationView(request, r));
      r["images"] = {o->output};
      return 0;
    }
    require(seg->segmentation.empty() && at->empty(), "--segmentation and --at go with a volume, not a model");
    RenderOptions options = *o;
    if (options.cpuLevel < 0 && options.cpuError == 0) options.cpuError = 2;
    if (options.gpuLevel < 0 && options.gpuPixels == 0) options.gpuPixels = 8;
    return render(options, r);
  }, exitCode);
}

}  // namespace isoatlas::app
