// bench_dvt: the torus drawing of Keller et al. (Fig. 7) beside OpenVDB's CSG on narrow-band level sets.
//   A sphere brush of radius 0.04 moves 120 steps of 3 degrees around a circle of radius 0.3 in the unit
//   cube (a union each step), then a brush of radius 0.02 carves a groove along the top of the tube
//   (a subtraction each step). Voxel size 5 % of the brush (1/512 of the cube) and 1.25 % (1/2048).
//   isoatlas: the four variants of Fig. 7 at both sizes: with and without the redundancy optimisation
//   (collapse every 10 writes) and hierarchical rasterisation; a step is rasterise + write (+ the
//   collapse when due).
//   OpenVDB: createLevelSetSphere (half width 3 voxels) + csgUnion / csgDifference per step.
//   Figures: ms per step (median, over the drawing and the carving; the drawing's mean too, with the
//   collapses every 10th step), nodes or active voxels, memory.
//   Plots bench/dvt_steps.png and dvt_nodes.png (512^3), dvt_steps_2048.png and dvt_nodes_2048.png.
//   With ISOATLAS_BENCH_GPU=1 the GPU backend too (ROHR), when the GL renderer is not a software one;
//   its rows name the GPU (and the CPU the peer ran on).
//   The brush in the window's tree view (`isoatlas view TREE.dvt`, ctrl-drag): the 512^3 drawing's
//   union steps as one tree, collapsed, then a stroke of kStrokeDabs sphere dabs of radius 0.02 along
//   the top of its tube, painted as the window paints (viewer::TreePainting: a write a dab; on the CPU
//   its streams uploaded after it) and drawn as the window draws (DvtRenderer's ray cast, 940 x 800:
//   the view beside the controls at the window's default size). Each dab is timed from its write to
//   its picture finished (glFinish), beside one frame at 60 Hz (the target: within a frame).
//   The CPU tree passes on whatever GL there is (llvmpipe here); the GPU's with ISOATLAS_BENCH_GPU=1.
//   With DATA: closed meshes of DATA/meshes into volumes, as `isoatlas edit MESH -o TREE.dvt` makes them
//   (the mesh's distance solid built, rasterised hierarchically, written into an empty tree and
//   collapsed), beside OpenVDB's meshToLevelSet (half width 3 voxels) at the same voxel size; median
//   of 3 runs.
// Usage: bench_dvt [DATA [torus|meshes|stroke]] (the torus and the stroke need no data; all parts by default).
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <numeric>

#include "bench/bench_util.h"
#include "core/gl/context.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/plot.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/solids/mesh_solid.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "render/orbit.h"
#include "render/dvt_render.h"
#include "viewer/tree_painting.h"

namespace isoatlas {
namespace dvt = edit::dvt;
namespace {

constexpr int kSteps = 120;
constexpr double kBrush = 0.04, kGroove = 0.02, kCircle = 0.3;

Vec3 along(int step, double lift) {
  const double a = step * 3.0 * std::numbers::pi / 180.0;
  return {0.5 + kCircle * std::cos(a), 0.5 + kCircle * std::sin(a), 0.5 + lift};
}
std::string sphere(const Vec3& c, double r) {
  return "sphere:" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) + "," + std::to_string(r);
}

// The unit cube as 2^K voxels a side.
dvt::TreeFrame unitCube(int k) {
  dvt::TreeFrame f;
  f.voxelSplits = k;
  const double h = 1.0 / double(f.voxelsPerAxis());
  f.spacing = {h, h, h};
  f.origin = {0.5 * h, 0.5 * h, 0.5 * h};
  return f;
}

struct Trace {
  std::vector<double> ms, size;  // per step: time and nodes (or active voxels)
  double bytesPeak = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

// `chain`: the GPU's writes as one chain of passes (TreeOptions::chainPasses), or driven pass by pass.
Trace drawOurs(int k, bool collapse, bool hierarchical, std::unique_ptr<dvt::TreePasses> passes, bool chain = true) {
  const dvt::TreeFrame frame = unitCube(k);
  const bool onGpu = passes->name() == "gpu";
  dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), std::move(passes),
                              {.nodeLimit = std::uint64_t(1) << 28, .collapseEvery = collapse ? 10 : 0, .chainPasses = chain});
  Trace t;
  for (int step = 0; step < 2 * kSteps; ++step) {
    const bool carve = step >= kSteps;
    const auto brush = dvt::parseBrush(carve ? sphere(along(step, kBrush), kGroove) : sphere(along(step, 0), kBrush));
    const auto start = std::chrono::steady_clock::now();
    tree.write(dvt::rasterise(*brush, frame, frame.voxelDepth(), hierarchical, std::uint64_t(1) << 28),
               carve ? dvt::Op::Subtract : dvt::Op::Union);
    if (onGpu) glFinish();
    t.ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    t.size.push_back(double(tree.nodeCount()));
    t.bytesPeak = std::max(t.bytesPeak, double(tree.bytes()));
  }
  return t;
}

Trace drawOpenVdb(int k) {
  const float voxel = float(1.0 / double(std::int64_t(1) << k));
  auto grid = openvdb::FloatGrid::create(3.0f * voxel);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  Trace t;
  for (int step = 0; step < 2 * kSteps; ++step) {
    const bool carve = step >= kSteps;
    const Vec3 c = carve ? along(step, kBrush) : along(step, 0);
    const auto start = std::chrono::steady_clock::now();
    auto brush = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(float(carve ? kGroove : kBrush),
                                                                         openvdb::Vec3f(float(c.x), float(c.y), float(c.z)), voxel, 3.0f);
    if (carve) openvdb::tools::csgDifference(*grid, *brush);
    else openvdb::tools::csgUnion(*grid, *brush);
    t.ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    t.size.push_back(double(grid->activeVoxelCount()));
    t.bytesPeak = std::max(t.bytesPeak, double(grid->memUsage()));
  }
  return t;
}

// A closed mesh into a volume of 2^splits voxels along its longest side: ours and OpenVDB's.
void meshIntoVolume(const std::string& data, const std::string& name, int splits) {
  const Mesh mesh = readMesh(data + "/meshes/" + name + ".off");
  const Box box = boundingBox(mesh.positions);
  const dvt::TreeFrame frame = dvt::frameAround(box.min, box.max, splits);
  const std::uint64_t limit = std::uint64_t(1) << 28;
  double nodes = 0, active = 0;
  const double ours = bench::medianSeconds(3, [&] {
    const auto solid = dvt::meshSolid(mesh, name);
    dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses(), {.nodeLimit = limit});
    tree.write(dvt::rasterise(*solid, frame, frame.voxelDepth(), true, limit), dvt::Op::Union);
    tree.collapse();
    nodes = double(tree.nodeCount());
  });
  std::vector<openvdb::Vec3s> points;
  for (const Vec3& p : mesh.positions) points.emplace_back(float(p.x), float(p.y), float(p.z));
  std::vector<openvdb::Vec3I> triangles;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) triangles.emplace_back(mesh.face(f)[0], mesh.face(f)[1], mesh.face(f)[2]);
  const auto transform = openvdb::math::Transform::createLinearTransform(frame.spacing.x);
  const double theirs = bench::medianSeconds(3, [&] {
    const auto grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 3.0f);
    active = double(grid->activeVoxelCount());
  });
  const std::string side = std::to_string(std::int64_t(1) << splits);
  const std::string caseName = name + " (" + std::to_string(mesh.faceCount()) + " triangles) into a volume, " + side + "^3";
  bench::report("dvt", caseName, "seconds", ours, "openvdb-meshToLevelSet", theirs);
  bench::report("dvt", caseName, "nodes (isoatlas) / active voxels (openvdb)", nodes, "openvdb", active);
}

std::vector<double> steps(int from, int to) {
  std::vector<double> x;
  for (int i = from; i < to; ++i) x.push_back(i + 1);
  return x;
}
std::vector<double> part(const std::vector<double>& v, int from, int to) { return {v.begin() + from, v.begin() + to}; }

}  // namespace
}  // namespace isoatlas

namespace isoatlas {
namespace {

// Our trace beside OpenVDB's: the step times of the drawing and the carving, memory, the final size.
void reportBeside(const std::string& name, const Trace& ours, const Trace& vdb, const std::string& device = "") {
  bench::report("dvt", name + ", union", "ms per step (median)", median(part(ours.ms, 0, kSteps)), "openvdb-csgUnion",
                median(part(vdb.ms, 0, kSteps)), true, device);
  bench::report("dvt", name + ", subtract", "ms per step (median)", median(part(ours.ms, kSteps, 2 * kSteps)), "openvdb-csgDifference",
                median(part(vdb.ms, kSteps, 2 * kSteps)), true, device);
  bench::report("dvt", name + ", union", "ms per step (mean, the collapses included)", mean(part(ours.ms, 0, kSteps)), "openvdb-csgUnion",
                mean(part(vdb.ms, 0, kSteps)), true, device);
  bench::report("dvt", name, "memory peak (MiB)", ours.bytesPeak / 1048576.0, "openvdb-memUsage", vdb.bytesPeak / 1048576.0, true, device);
  bench::report("dvt", name, "nodes (isoatlas) / active voxels (openvdb), final", ours.size.back(), "openvdb", vdb.size.back(), true, device);
}

constexpr int kStrokeDabs = 40;

// The stroke in the tree view (the header's "brush in the window's tree view"): ms a dab, its write
// to its picture, median and longest.
void strokeLatency(levelset::Backend backend, const std::string& device) {
  const dvt::TreeFrame frame = unitCube(9);
  dvt::DynamicVolumeTree drawing(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses());
  for (int step = 0; step < kSteps; ++step)
    drawing.write(dvt::rasterise(*dvt::parseBrush(sphere(along(step, 0), kBrush)), frame, frame.voxelDepth()), dvt::Op::Union);
  drawing.collapse();
  const dvt::VolumeTree tree = drawing.tree();
  viewer::TreePainting painting(tree, backend);
  render::DvtRenderer renderer;
  const int width = 940, height = 800;
  gl::Framebuffer target(width, height);
  const render::Camera camera = render::Orbit{}.camera(render::insideBounds(tree), width, height);  // the window's first view
  std::vector<double> ms, writeMs;
  for (int dab = 0; dab < kStrokeDabs; ++dab) {
    const auto start = std::chrono::steady_clock::now();
    painting.dabTo(along(dab, kBrush), kGroove, dab % 2 == 0);  // union and carve in turn: the tree keeps changing
    if (painting.backend() == "gpu") glFinish();
    writeMs.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    target.bind();
    renderer.draw(painting.buffers(), painting.nodeCount(), painting.frame(), {.camera = camera});
    glFinish();
    ms.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const std::string name = "brush stroke in the tree view, 512^3 torus (" + std::to_string(tree.nodeCount()) + " nodes), " +
                           std::to_string(kStrokeDabs) + " dabs, " + painting.backend() + " tree passes, ray cast " +
                           std::to_string(width) + " x " + std::to_string(height);
  bench::report("dvt", name, "ms from a dab's write to its picture (median)", median(ms), "one frame at 60 Hz", 1000.0 / 60, true, device);
  bench::report("dvt", name, "ms of it in the write (median; on the CPU with the streams' upload)", median(writeMs), "one frame at 60 Hz",
                1000.0 / 60, true, device);
  bench::report("dvt", name, "ms from a dab's write to its picture (longest)", *std::max_element(ms.begin(), ms.end()), "one frame at 60 Hz",
                1000.0 / 60, true, device);
}

// A GL context on a real GPU when ISOATLAS_BENCH_GPU=1 asks for one; none on a software renderer,
// whose figures would say nothing of a GPU.
std::unique_ptr<gl::Context> gpuContext() {
  const char* asked = std::getenv("ISOATLAS_BENCH_GPU");
  if (!asked || std::string(asked) != "1") return nullptr;
  auto context = gl::Context::headless();
  if (context->info().software()) {
    std::fprintf(stderr, "bench_dvt: ISOATLAS_BENCH_GPU=1, but GL runs on %s (software): no GPU figures\n",
                 context->info().renderer.c_str());
    return nullptr;
  }
  return context;
}

}  // namespace
}  // namespace isoatlas

int main(int argc, char** argv) {
  using namespace isoatlas;
  openvdb::initialize();
  const std::string part = argc > 2 ? argv[2] : "";
  if (argc > 1 && (part.empty() || part == "meshes")) {
    for (const char* name : {"armadillo", "bunny00"})
      for (const int splits : {8, 9}) meshIntoVolume(argv[1], name, splits);
  }
  if (part == "meshes") return 0;
  const std::unique_ptr<gl::Context> gpu = gpuContext();
  const std::string device = gpu ? gpu->info().renderer + " (OpenVDB on " + bench::machineName() + ")" : "";
  if (part.empty() || part == "stroke") {
    // The window draws with GL whatever the tree passes: llvmpipe here, unless a GPU is asked for.
    const std::unique_ptr<gl::Context> software = gpu ? nullptr : gl::Context::headless();
    const std::string renderer = gpu ? gpu->info().renderer : software->info().renderer;
    strokeLatency(levelset::Backend::Cpu, renderer + " (" + bench::machineName() + ")");
    if (gpu) strokeLatency(levelset::Backend::Gpu, renderer + " (" + bench::machineName() + ")");
    if (part == "stroke") return 0;
  }
  const std::string dir = ISOATLAS_BENCH_DIR;
  for (const int k : {9, 11}) {
    const std::string size = k == 9 ? "voxel 5% of the brush (512^3)" : "voxel 1.25% of the brush (2048^3)";
    const Trace vdb = drawOpenVdb(k);
    struct Variant {
      const char* name;
      bool collapse, hierarchical;
    };
    std::vector<PlotSeries> timeSeries, nodeSeries;
    for (const Variant& v : {Variant{"ROHR", true, true}, Variant{"HR", false, true}, Variant{"RO", true, false}, Variant{"NO", false, false}}) {
      const Trace ours = drawOurs(k, v.collapse, v.hierarchical, dvt::makeCpuTreePasses());
      reportBeside(std::string("torus drawing, ") + v.name + ", " + size, ours, vdb);
      timeSeries.push_back({std::string(v.name), steps(0, 2 * kSteps), ours.ms});
      nodeSeries.push_back({std::string(v.name), steps(0, 2 * kSteps), ours.size});
    }
    if (gpu) {
      const Trace ours = drawOurs(k, true, true, dvt::makeGpuTreePasses());
      reportBeside(std::string("torus drawing, ROHR on the GPU, ") + size, ours, vdb, device);
      timeSeries.push_back({"ROHR, GPU", steps(0, 2 * kSteps), ours.ms});
      nodeSeries.push_back({"ROHR, GPU", steps(0, 2 * kSteps), ours.size});
      // The same passes driven by the host, reading counters between them: what the chain saves.
      const Trace driven = drawOurs(k, true, true, dvt::makeGpuTreePasses(), false);
      reportBeside(std::string("torus drawing, ROHR on the GPU, host-driven passes, ") + size, driven, vdb, device);
      timeSeries.push_back({"ROHR, GPU, host-driven", steps(0, 2 * kSteps), driven.ms});
    }
    timeSeries.push_back({"OpenVDB", steps(0, 2 * kSteps), vdb.ms});
    const std::string suffix = k == 9 ? "" : "_2048";
    writePng(dir + "/dvt_steps" + suffix + ".png",
             linePlot(timeSeries, {.title = "Torus drawing (steps 1-120), then carving (121-240), " + size, .xLabel = "step",
                                   .yLabel = "ms per step"}));
    writePng(dir + "/dvt_nodes" + suffix + ".png",
             linePlot(nodeSeries, {.title = "Tree nodes per step, " + size, .xLabel = "step", .yLabel = "nodes"}));
  }
  return 0;
}
