// TreePasses: the data-parallel passes a DVT write and collapse are made of (Keller et al., Alg. 3.1),
// on the CPU (cpu_tree_passes, TBB) or the GPU (gpu_tree_passes, GL 4.5 compute). Both apply
// tree_rules.h to pre-order streams (volume_tree.h) with a mark per node: the GPU to the one pointer
// and node stream, the CPU to each brick of a tree it keeps cut into bricks, in a compact stream of
// its own (download() gives the one stream, the GPU's node for node). DynamicVolumeTree drives them. One iteration of a write:
//   mark         per input voxel: walk to its target depth; write leaves of that depth, mark a coarser
//                leaf for expansion (and note it as the voxel's hit), mark a finer subtree for
//                reduction (its pre-order range, for one scan that removes it whole)
//   plan         per input voxel: what its leaf's expansion needs for it (the ancestors of the voxel
//                below the leaf not shared with the previous voxel; voxels in one leaf are
//                consecutive, being in pre-order); per node: how many nodes it becomes (0 removed,
//                1, or 1 + the new subtree under an expanded leaf), prefix-summed into the remap stream
//   restructure  per node: scatter to its new index with its pointers remapped; an expanded leaf
//                writes its new subtree after itself: the smallest that holds its voxels' cells, cut
//                where its values saturate (expansionCut) and, on the GPU, kExpandLevels below the
//                leaf (voxels deeper expand on in the next iteration)
// The paper adds one level per iteration; the tree after the write is the same (expansionCut stops
// where a level at a time would), so the CPU grows each expansion to the bottom and ends a write in
// one restructure (restructureFinishesWrites).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "edit/dvt/tree_rules.h"
#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt {

// A write or collapse run by the backend through to its end (TreePasses::writeChained, collapseChained).
struct ChainRun {
  int iterations = 0;   // restructures
  int reads = 0;        // times the host read the passes' state back: a write's 1 unless the streams had to grow
  bool finished = true; // false: stopped before the node limit's check, for the caller's iterations
};

struct Plan {
  std::uint64_t nodes = 0;    // after the restructure
  std::uint64_t changes = 0;  // nodes removed, expanded, reduced or collapsed: 0 when the tree is final
};

class TreePasses {
public:
  virtual ~TreePasses() = default;
  virtual std::string name() const = 0;  // "cpu" or "gpu"
  virtual void load(const VolumeTree& tree) = 0;
  virtual VolumeTree download() const = 0;
  virtual std::uint64_t nodeCount() const = 0;
  // Memory held: the streams and marks at their capacity, the input and the remap stream.
  virtual std::uint64_t bytes() const = 0;
  virtual void setInput(std::vector<InputVoxel> input) = 0;  // in pre-order
  // Clears the marks, then marks for the input; returns how many marks were set (with repeats).
  virtual std::uint64_t mark(Op op) = 0;
  // Clears the marks, then marks nodes to collapse; returns how many. The GPU marks inner nodes whose
  // two children are collapsible (a level a pass), the CPU the roots of the largest subtrees of one
  // uniform value; marking and restructuring until none are left ends with the same tree.
  virtual std::uint64_t markCollapse() = 0;
  // The remap stream for the marks; expansions count only when allowed (the node budget).
  virtual Plan plan(bool allowExpand) = 0;
  // Makes the streams of the last plan; storage grows by doubling, to at most `nodeLimit` nodes.
  virtual void restructure(const Plan& plan, bool allowExpand, std::uint64_t nodeLimit) = 0;
  // Whether a write's restructure leaves nothing for another mark to do (the CPU's: its expansions
  // go all the way down and give the voxels their values), so the write can end without one.
  virtual bool restructureFinishesWrites() const { return false; }
  // The write of the last setInput as one chain of passes the host does not wait on between, where the
  // backend has one (the GPU: each pass sized by the one before, through indirect dispatch; the host
  // reads the passes' state once at the end). Nothing when it has none: the caller iterates mark,
  // plan and restructure. Where a restructure could pass `nodeLimit`, the chain stops before it
  // (finished false) and the caller's iterations finish the write from there, with the limit's rule.
  virtual std::optional<ChainRun> writeChained(Op op, std::uint64_t nodeLimit) {
    (void)op, (void)nodeLimit;
    return std::nullopt;
  }
  // A collapse (markCollapse, plan, restructure until nothing is marked) as such a chain, where the
  // backend has one; the host reads its state once a batch of iterations.
  virtual std::optional<ChainRun> collapseChained() { return std::nullopt; }
};

}  // namespace isoatlas::edit::dvt
