// The edits `edit` and `run` share: a volume tree from a segmentation, a closed mesh or a .dvt file,
// union and subtract steps (brushes or meshes) applied in order on the chosen backend, collapsed at
// the end, and the result as a mask in the input's geometry, a mesh (through extract/) or a tree.
#pragma once
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/gpu.h"
#include "core/volume.h"
#include "core/mesh.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/solids/solid.h"
#include "render/dvt_render.h"

namespace isoatlas::pipeline {

struct EditStep {
  edit::dvt::Op op = edit::dvt::Op::Union;
  std::string shape;  // sphere:..., box:..., capsule:..., torus:..., mesh:FILE (edit/dvt/solid.h)
};

// The steps' solids: brushes parsed, meshes read (throws Error naming the shape or the file).
std::vector<std::unique_ptr<edit::dvt::DistanceSolid>> stepSolids(const std::vector<EditStep>& steps);

struct EditRequest {
  std::optional<std::uint32_t> depth;  // default: the input's voxels
  std::vector<EditStep> steps;
  bool hierarchical = true;             // hierarchical rasterisation (rasterise.h)
  std::uint64_t nodeLimit = edit::dvt::TreeOptions{}.nodeLimit;
  int collapseEvery = 0;                // also collapse after every k edits (0: only at the end)
};

struct EditedTree {
  std::unique_ptr<edit::dvt::DynamicVolumeTree> tree;
  std::uint32_t depth = 0;
  std::string backend;
  double secondsWrite = 0, secondsCollapse = 0;  // collapses: every k writes and the last one
  std::uint64_t inputVoxels = 0, iterations = 0;   // iterations: mark-restructure rounds, all writes
  std::uint64_t collapses = 0;                     // every k writes and the last one
  // nodes, leaves, depth_max, seconds_write, seconds_collapse, collapses, bytes, backend, depth,
  // input_voxels, write_iterations;
  // `streams`: the tree as tree->tree() gives it (a copy, or a read-back from the GPU: take it once)
  nlohmann::json figures(const edit::dvt::VolumeTree& streams) const;
};

// What an edit starts from, read and checked before any GPU work: a segmentation (mask or phi volume),
// a closed mesh or a saved tree; the steps' solids (brushes parsed, meshes read); and the frame and
// depth of the tree, fixed once here.
struct EditInput {
  std::unique_ptr<const Volume> volume;                    // a segmentation, held for `solid` to read
  std::optional<edit::dvt::VolumeTree> tree;           // a saved tree
  std::unique_ptr<const edit::dvt::Solid> solid;       // the segmentation's or the mesh's; none for a tree
  std::vector<std::unique_ptr<edit::dvt::DistanceSolid>> solids;  // one per step
  edit::dvt::TreeFrame frame;  // a segmentation's grid, a saved tree's, a box around a mesh
  std::uint32_t depth = 0;         // the request's, else the input's voxels (24 for a mesh)
};
// Both throw Error naming the file or the shape, and past the depth limit.
EditInput readEditInput(const std::string& input, const EditRequest& request);
EditInput editInputOf(Volume segmentation, const EditRequest& request);
// Refuses (Error) an edit whose shapes would make more voxels than the node limit at its depth, from
// their coarse levels: cheap, before any GPU work (rasterise would find it later).
void checkEditBudget(const EditInput& input, const EditRequest& request);

// A tree of a level set's segmentation in its own grid, read from its pages where its backend keeps
// them (no dense phi), at the request's depth (default its voxels), node limit and collapse period
// (its steps are not applied: applySteps).
EditedTree treeOfLevelSet(const levelset::LevelSet& levelSet, const EditRequest& request, Gpu& gpu);
// The same on `backend`, in the current context when it is the GPU (the window's).
EditedTree treeOfLevelSet(const levelset::LevelSet& levelSet, const EditRequest& request, levelset::Backend backend);
// The input's tree with the request's steps applied, then collapsed.
EditedTree applyEdits(const EditInput& input, const EditRequest& request, Gpu& gpu);
void applySteps(EditedTree& edited, const EditRequest& request, const std::vector<std::unique_ptr<edit::dvt::DistanceSolid>>& solids);
// A picture of the edited tree: from the GPU tree's own buffers, else `streams` uploaded.
Image renderEditedTree(const EditedTree& edited, const edit::dvt::VolumeTree& streams, const render::DvtView& view, Gpu& gpu);

}  // namespace isoatlas::pipeline
