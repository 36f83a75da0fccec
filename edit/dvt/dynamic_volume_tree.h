// DynamicVolumeTree: the tree (volume_tree.h) on a backend (tree_passes.h), changed by writes of
// input voxels (rasterise.h, volume_input.h) until nothing changes, and collapsed on demand or every
// k writes (Keller et al., Alg. 3.1 and sec. 4.3).
//   Union: every cell the input holds inside becomes inside (leaf values: the larger); subtract: every
//   cell it holds inside becomes outside (the smaller of the leaf and the input's complement). A leaf
//   coarser than an input voxel is split down to it (unless the write cannot change it); a subtree
//   finer than an input voxel is replaced by one leaf at the voxel's depth (the input's resolution
//   wins there, as in the paper).
//   The node budget: streams grow (doubling) up to `nodeLimit` nodes. A write that would need more
//   stops expanding, finishes its removals so the tree stays valid, and throws Error: the edit is then
//   applied only where it did not need new nodes.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "edit/dvt/tree_passes.h"

namespace isoatlas::edit::dvt {

struct TreeOptions {
  std::uint64_t nodeLimit = kDefaultNodeLimit;  // at most kMaxTreeNodes
  int collapseEvery = 0;  // 0: only when collapse() is called
  // Whether writes and collapses run as the backend's chains of passes where it has them
  // (TreePasses::writeChained, collapseChained); false: the host drives every pass and reads its
  // counters (the GPU's stepwise path, to compare).
  bool chainPasses = true;
};

struct WriteStats {
  int iterations = 0;
  int chainReads = 0;  // reads back of a chained write's state (0: the host drove the passes)
  std::uint64_t inputVoxels = 0, nodes = 0;
  double seconds = 0, collapseSeconds = 0;  // collapseSeconds: an automatic collapse after this write
  bool collapsed = false;                   // whether that collapse ran (every k writes)
};

class DynamicVolumeTree {
public:
  DynamicVolumeTree(const VolumeTree& tree, std::unique_ptr<TreePasses> passes, const TreeOptions& options = {});
  WriteStats write(PreOrderInput input, Op op);
  // Joins equal uniform siblings until none are left; returns the nodes removed.
  std::uint64_t collapse();
  VolumeTree tree() const { return passes_->download(); }
  std::uint64_t nodeCount() const { return passes_->nodeCount(); }
  std::uint64_t bytes() const { return passes_->bytes(); }
  const TreeFrame& frame() const { return frame_; }
  std::string backend() const { return passes_->name(); }
  TreePasses& passes() { return *passes_; }

private:
  TreeFrame frame_;
  std::unique_ptr<TreePasses> passes_;
  TreeOptions options_;
  int writes_ = 0;
};

}  // namespace isoatlas::edit::dvt
