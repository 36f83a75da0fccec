#version 450
// The plan pass's part per input voxel (tree_passes.h, CpuTreePasses::planInput): the new nodes its
// leaf's expansion needs for it (down to the cut), and the bounds of the leaf's run of voxels.
layout(local_size_x = 64) in;
#include "tree_rules.glsl"

void main() {
  uint i = threadIndex();
  if (i >= count) return;
  uint leaf = hits[i];
  if (leaf == NO_HIT) return;
  uvec2 c = inputCell(i);
  bool first = i == 0u || hits[i - 1u] != leaf, last = i + 1u == count || hits[i + 1u] != leaf;
  uint leafDepth = depthOf(cells[leaf]), cut = min(depthOf(c), expansionCut(pointers[leaf].value, leafDepth));
  uint known = first ? leafDepth : min(commonDepth(inputCell(i - 1u), c) + 1u, cut);
  atomicAdd(expansions[leaf].size, 2u * (cut - known));
  if (first) expansions[leaf].begin = i;
  if (last) expansions[leaf].end = i + 1u;
}
