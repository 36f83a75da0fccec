#include "app/volume_editing.h"

#include <chrono>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "levelset/dvt/cpu_tree_passes.h"
#include "levelset/dvt/dvt_file.h"
#include "levelset/dvt/gpu_tree_passes.h"
#include "levelset/dvt/mesh_solid.h"
#include "levelset/dvt/rasterise.h"
#include "levelset/dvt/volume_solid.h"
#include "levelset/level_set.h"

namespace isoatlas::app {
namespace dvt = levelset::dvt;
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::uint32_t checkedDepth(std::optional<std::uint32_t> depth, const dvt::TreeFrame& frame) {
  const std::uint32_t d = depth.value_or(frame.voxelDepth());
  require(d <= std::uint32_t(dvt::kMaxDepth),
          "--depth " + std::to_string(d) + " is past the tree's limit of " + std::to_string(dvt::kMaxDepth));
  return d;
}

EditedTree start(const dvt::VolumeTree& tree, std::array<std::int64_t, 3> dims, std::uint32_t depth, Gpu& gpu,
                 std::uint64_t nodeLimit, int collapseEvery = 0) {
  EditedTree e;
  const bool onGpu = gpu.backend == levelset::Backend::Gpu;
  auto passes = onGpu ? dvt::makeGpuTreePasses(gpu.needGl()) : dvt::makeCpuTreePasses();
  e.tree = std::make_unique<dvt::DynamicVolumeTree>(tree, std::move(passes), dvt::TreeOptions{.nodeLimit = nodeLimit, .collapseEvery = collapseEvery});
  e.dims = dims, e.depth = depth, e.backend = onGpu ? "gpu" : "cpu";
  return e;
}

void write(EditedTree& e, const dvt::Solid& solid, dvt::Op op, bool hierarchical) {
  const auto begin = std::chrono::steady_clock::now();
  dvt::PreOrderInput input = dvt::rasterise(solid, e.tree->frame(), e.depth, hierarchical);
  e.inputVoxels += input.size();
  e.tree->write(std::move(input), op);
  e.secondsWrite += secondsSince(begin);
}

}  // namespace

nlohmann::json EditedTree::figures(const dvt::VolumeTree& t) const {
  return {{"nodes", t.nodeCount()}, {"leaves", t.leafCount()}, {"depth_max", t.maxDepth()}, {"depth", depth},
          {"seconds_write", secondsWrite}, {"seconds_collapse", secondsCollapse}, {"bytes", tree->bytes()},
          {"backend", backend}, {"input_voxels", inputVoxels}};
}

EditedTree treeOfVolume(const Volume& volume, const EditRequest& request, Gpu& gpu) {
  const dvt::TreeFrame frame = dvt::frameOf(volume);
  EditedTree e = start(dvt::VolumeTree::empty(frame), volume.dims, checkedDepth(request.depth, frame), gpu, request.nodeLimit,
                       request.collapseEvery);
  write(e, dvt::VolumeSolid(volume), dvt::Op::Union, true);
  return e;
}

void addEditStepOptions(CLI::App& sub, const std::shared_ptr<std::vector<EditStep>>& steps) {
  const std::string shapes =
      "SHAPE in world coordinates: sphere:X,Y,Z,R  box:X0,Y0,Z0,X1,Y1,Z1  capsule:X0,Y0,Z0,X1,Y1,Z1,R  torus:X,Y,Z,R,r  mesh:FILE";
  // Callbacks as each option is parsed, so unions and subtractions keep the command line's order.
  sub.add_option_function<std::string>("--union", [steps](const std::string& s) { steps->push_back({dvt::Op::Union, s}); },
                                       "add a " + shapes + "; repeatable")
      ->trigger_on_parse();
  sub.add_option_function<std::string>("--subtract", [steps](const std::string& s) { steps->push_back({dvt::Op::Subtract, s}); },
                                       "carve a SHAPE out; repeatable, applied in order with --union")
      ->trigger_on_parse();
}

std::vector<std::unique_ptr<dvt::DistanceSolid>> stepSolids(const std::vector<EditStep>& steps) {
  std::vector<std::unique_ptr<dvt::DistanceSolid>> solids;
  for (const EditStep& step : steps) {
    if (step.shape.starts_with("mesh:")) {
      const std::string file = step.shape.substr(5);
      solids.push_back(dvt::meshSolid(readMesh(file), file));
    } else {
      solids.push_back(dvt::parseBrush(step.shape));
    }
  }
  return solids;
}

EditedTree treeOfLevelSet(const levelset::LevelSet& levelSet, const EditRequest& request, Gpu& gpu) {
  const dvt::TreeFrame frame = dvt::frameOf(levelSet.geometry());
  EditedTree e = start(dvt::VolumeTree::empty(frame), levelSet.geometry().dims, checkedDepth(request.depth, frame), gpu,
                       request.nodeLimit, request.collapseEvery);
  write(e, dvt::VolumeSolid(levelSet), dvt::Op::Union, true);
  return e;
}

EditInput readEditInput(const std::string& path, const EditRequest& request) {
  require(!request.depth || *request.depth <= std::uint32_t(dvt::kMaxDepth),
          "--depth " + std::to_string(request.depth.value_or(0)) + " is past the tree's limit of " + std::to_string(dvt::kMaxDepth));
  EditInput in;
  in.solids = stepSolids(request.steps);
  if (endsWith(path, ".dvt")) {
    in.tree = dvt::readDvt(path);
  } else if (isMeshPath(path)) {
    in.mesh = readMesh(path);
    in.meshSolid = dvt::meshSolid(*in.mesh, path);
  } else {
    in.volume = readVolume(path);
  }
  return in;
}

EditedTree applyEdits(const EditInput& input, const EditRequest& request, Gpu& gpu) {
  EditedTree e;
  if (input.tree) {
    const auto n = input.tree->frame.voxelsPerAxis();
    e = start(*input.tree, {n, n, n}, checkedDepth(request.depth, input.tree->frame), gpu, request.nodeLimit, request.collapseEvery);
  } else if (input.mesh) {
    const Mesh& mesh = *input.mesh;
    Vec3 lo = mesh.positions.front(), hi = lo;
    for (const Vec3& p : mesh.positions)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    const std::uint32_t depth = request.depth.value_or(24);
    const dvt::TreeFrame frame = dvt::frameAround(lo, hi, int(std::min<std::uint32_t>((depth + 2) / 3, dvt::kMaxDepth / 3)));
    const auto n = frame.voxelsPerAxis();
    e = start(dvt::VolumeTree::empty(frame), {n, n, n}, depth, gpu, request.nodeLimit, request.collapseEvery);
    write(e, *input.meshSolid, dvt::Op::Union, request.hierarchical);
  } else {
    e = treeOfVolume(*input.volume, request, gpu);
  }
  applySteps(e, request, input.solids);
  return e;
}

void applySteps(EditedTree& e, const EditRequest& request, const std::vector<std::unique_ptr<dvt::DistanceSolid>>& solids) {
  for (std::size_t i = 0; i < request.steps.size(); ++i) {
    const EditStep& step = request.steps[i];
    write(e, *solids.at(i), step.op, request.hierarchical);
    logInfo("edit: " + std::string(step.op == dvt::Op::Union ? "union " : "subtract ") + step.shape + " (" +
            std::to_string(i + 1) + "/" + std::to_string(request.steps.size()) + "), " + std::to_string(e.tree->nodeCount()) + " nodes");
  }
  const auto begin = std::chrono::steady_clock::now();
  e.tree->collapse();
  e.secondsCollapse = secondsSince(begin);
}

Image renderEditedTree(const EditedTree& e, const dvt::VolumeTree& streams, const viewer::DvtView& view, Gpu& gpu) {
  gpu.needGl();
  if (e.backend != "gpu") return viewer::renderTree(streams, view);
  return viewer::renderTree(dvt::gpuTreeBuffers(e.tree->passes()), e.tree->nodeCount(), e.tree->frame(), view);
}


}  // namespace isoatlas::app
