#include "pipeline/volume_editing.h"

#include <chrono>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dvt_file.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/solids/mesh_solid.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "levelset/level_set.h"

namespace isoatlas::pipeline {
namespace dvt = edit::dvt;
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

constexpr std::uint32_t kMeshDepth = 24;  // a mesh's default depth: 256 voxels a side

void requireDepthLimit(std::optional<std::uint32_t> depth) {
  require(!depth || *depth <= std::uint32_t(dvt::kMaxDepth),
          "--depth " + std::to_string(depth.value_or(0)) + " is past the tree's limit of " + std::to_string(dvt::kMaxDepth));
}

std::uint32_t checkedDepth(std::optional<std::uint32_t> depth, const dvt::TreeFrame& frame) {
  const std::uint32_t d = depth.value_or(frame.voxelDepth());
  requireDepthLimit(d);
  return d;
}

// A mesh has no voxels: its frame is a box around it, split finely enough for its depth.
dvt::TreeFrame frameAroundMesh(const Mesh& mesh, std::uint32_t depth) {
  const Box box = boundingBox(mesh.positions);
  return dvt::frameAround(box.min, box.max, int(std::min<std::uint32_t>((depth + 2) / 3, dvt::kMaxDepth / 3)));
}

EditedTree start(const dvt::VolumeTree& tree, std::uint32_t depth, levelset::Backend backend, const EditRequest& request) {
  EditedTree e;
  const bool onGpu = backend == levelset::Backend::Gpu;
  auto passes = onGpu ? dvt::makeGpuTreePasses() : dvt::makeCpuTreePasses();
  e.tree = std::make_unique<dvt::DynamicVolumeTree>(
      tree, std::move(passes), dvt::TreeOptions{.nodeLimit = request.nodeLimit, .collapseEvery = request.collapseEvery});
  e.depth = depth, e.backend = onGpu ? "gpu" : "cpu";
  return e;
}

// The backend of a command's stage, its context made when it is the GPU.
levelset::Backend backendOf(Gpu& gpu) {
  if (gpu.backend == levelset::Backend::Gpu) gpu.needGl();
  return gpu.backend;
}

// A segmentation's conversion is always rasterised hierarchically; `--flat` is for the shapes (and a
// mesh input).
bool inputHierarchical(const EditInput& input, const EditRequest& request) {
  return input.volume != nullptr || request.hierarchical;
}

void write(EditedTree& e, const dvt::Solid& solid, dvt::Op op, const EditRequest& request, bool hierarchical) {
  const auto begin = std::chrono::steady_clock::now();
  dvt::PreOrderInput input = dvt::rasterise(solid, e.tree->frame(), e.depth, hierarchical, request.nodeLimit);
  e.inputVoxels += input.size();
  const dvt::WriteStats stats = e.tree->write(std::move(input), op);
  e.iterations += std::uint64_t(stats.iterations);
  e.secondsCollapse += stats.collapseSeconds;  // a collapse every k writes (--collapse-every)
  e.collapses += stats.collapsed;
  e.secondsWrite += secondsSince(begin) - stats.collapseSeconds;
}

}  // namespace

nlohmann::json EditedTree::figures(const dvt::VolumeTree& t) const {
  return {{"nodes", t.nodeCount()}, {"leaves", t.leafCount()}, {"depth_max", t.maxDepth()}, {"depth", depth},
          {"seconds_write", secondsWrite}, {"seconds_collapse", secondsCollapse}, {"collapses", collapses}, {"bytes", tree->bytes()},
          {"backend", backend}, {"input_voxels", inputVoxels}, {"write_iterations", iterations}};
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
  return treeOfLevelSet(levelSet, request, backendOf(gpu));
}

EditedTree treeOfLevelSet(const levelset::LevelSet& levelSet, const EditRequest& request, levelset::Backend backend) {
  const dvt::TreeFrame frame = dvt::frameOf(levelSet.geometry());
  EditedTree e = start(dvt::VolumeTree::empty(frame), checkedDepth(request.depth, frame), backend, request);
  write(e, dvt::VolumeSolid(levelSet), dvt::Op::Union, request, true);
  return e;
}

namespace {

void setSegmentation(EditInput& in, Volume segmentation, const EditRequest& request) {
  in.volume = std::make_unique<const Volume>(std::move(segmentation));
  in.solid = std::make_unique<const dvt::VolumeSolid>(*in.volume);
  in.frame = dvt::frameOf(*in.volume);
  in.depth = checkedDepth(request.depth, in.frame);
}

}  // namespace

EditInput editInputOf(Volume segmentation, const EditRequest& request) {
  requireDepthLimit(request.depth);
  EditInput in;
  in.solids = stepSolids(request.steps);
  setSegmentation(in, std::move(segmentation), request);
  return in;
}

EditInput readEditInput(const std::string& path, const EditRequest& request) {
  requireDepthLimit(request.depth);
  EditInput in;
  in.solids = stepSolids(request.steps);  // first: a mistyped shape is told before a large input is read
  if (endsWith(path, ".dvt")) {
    in.tree = dvt::readDvt(path);
    in.frame = in.tree->frame;
    in.depth = checkedDepth(request.depth, in.frame);
  } else if (isMeshPath(path)) {
    const Mesh mesh = readMesh(path);
    in.solid = dvt::meshSolid(mesh, path);
    const std::uint32_t depth = request.depth.value_or(kMeshDepth);
    in.frame = frameAroundMesh(mesh, depth);
    in.depth = checkedDepth(depth, in.frame);
  } else {
    setSegmentation(in, readVolume(path), request);
  }
  return in;
}

void checkEditBudget(const EditInput& input, const EditRequest& request) {
  if (input.solid) dvt::checkVoxelBudget(*input.solid, input.frame, input.depth, inputHierarchical(input, request), request.nodeLimit);
  for (const auto& solid : input.solids) dvt::checkVoxelBudget(*solid, input.frame, input.depth, request.hierarchical, request.nodeLimit);
}

EditedTree applyEdits(const EditInput& input, const EditRequest& request, Gpu& gpu) {
  EditedTree e = start(input.tree ? *input.tree : dvt::VolumeTree::empty(input.frame), input.depth, backendOf(gpu), request);
  if (input.solid) write(e, *input.solid, dvt::Op::Union, request, inputHierarchical(input, request));
  applySteps(e, request, input.solids);
  return e;
}

void applySteps(EditedTree& e, const EditRequest& request, const std::vector<std::unique_ptr<dvt::DistanceSolid>>& solids) {
  for (std::size_t i = 0; i < request.steps.size(); ++i) {
    const EditStep& step = request.steps[i];
    write(e, *solids.at(i), step.op, request, request.hierarchical);
    logInfo("edit: " + std::string(step.op == dvt::Op::Union ? "union " : "subtract ") + step.shape + " (" +
            std::to_string(i + 1) + "/" + std::to_string(request.steps.size()) + "), " + std::to_string(e.tree->nodeCount()) + " nodes");
  }
  const auto begin = std::chrono::steady_clock::now();
  e.tree->collapse();
  e.secondsCollapse += secondsSince(begin);
  ++e.collapses;
}

Image renderEditedTree(const EditedTree& e, const dvt::VolumeTree& streams, const render::DvtView& view, Gpu& gpu) {
  gpu.needGl();
  if (e.backend != "gpu") return render::renderTree(streams, view);
  return render::renderTree(dvt::gpuTreeBuffers(e.tree->passes()), e.tree->nodeCount(), e.tree->frame(), view);
}


}  // namespace isoatlas::pipeline
