// rasterise: a solid (solid.h) as DVT input voxels down to a target depth (Keller et al., Alg. 4.1).
// Hierarchical: from the root, cells wholly inside become one voxel at their own depth, cells wholly
// outside are dropped, crossed cells are split until the target depth, where they keep their band
// value. Not hierarchical (the paper's variant without it): every cell with some inside is split down
// to the target depth, so every voxel is at that depth. Either way the voxels are disjoint cells and
// the same set of target-depth centres is inside. Runs on the CPU with TBB for both backends and
// makes the voxels in pre-order (depth first, lower half first), as a write takes them.
#pragma once
#include <vector>

#include "edit/solids/solid.h"
#include "edit/dvt/tree_rules.h"

namespace isoatlas::edit::dvt {

// Throws Error when targetDepth is past kMaxDepth, and when the voxels would be more than `voxelLimit`
// (a write's input is held whole; a tree would hold at least as many leaves): at once where the
// coarse levels foretell twice that (checkVoxelBudget), else as soon as the count passes the limit.
PreOrderInput rasterise(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical = true,
                        std::uint64_t voxelLimit = kDefaultNodeLimit);
// The coarse levels' check alone (rasterise's first pass; at most 64^3 cells classified): the cells
// that make voxels, counted down to depth 18 and extrapolated to targetDepth by their growth over the
// last three levels. For a command to refuse a depth before it starts any work.
void checkVoxelBudget(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical = true,
                      std::uint64_t voxelLimit = kDefaultNodeLimit);

}  // namespace isoatlas::edit::dvt
