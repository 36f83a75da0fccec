// rasterise: a solid (solid.h) as DVT input voxels down to a target depth (Jung et al., Alg. 4.1).
// Hierarchical: from the root, cells wholly inside become one voxel at their own depth, cells wholly
// outside are dropped, crossed cells are split until the target depth, where they keep their band
// value. Not hierarchical (the paper's variant without it): every cell with some inside is split down
// to the target depth, so every voxel is at that depth. Either way the voxels are disjoint cells and
// the same set of target-depth centres is inside. Runs on the CPU with TBB for both backends and
// makes the voxels in pre-order (depth first, lower half first), as a write takes them.
#pragma once
#include <vector>

#include "levelset/dvt/solid.h"
#include "levelset/dvt/tree_rules.h"

namespace isoatlas::levelset::dvt {

// Throws Error when targetDepth is past kMaxDepth.
PreOrderInput rasterise(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical = true);

}  // namespace isoatlas::levelset::dvt
