#version 450
// The mark pass (tree_passes.h): per input voxel (MARK_INPUT) the walk of CpuTreePasses::markFor, or
// per node the collapse test (markCollapse). Counts the marks set in `counter`.
layout(local_size_x = 64) in;
#include "tree_rules.glsl"

void main() {
  uint i = threadIndex();
#ifdef MARK_INPUT
  if (i >= count) return;
  InputVoxel v = inputs[i];
  uvec2 cell = uvec2(v.xy, v.zd);
  uint target = depthOf(cell);
  float incoming = inputValue(op, v.value);
  uint n = 0u;
  hits[i] = NO_HIT;
  for (uint d = 0u;; ++d) {
    Pointer p = pointers[n];
    if (isLeaf(p)) {
      if (d == target) {
        float nv = combined(op, p.value, incoming);
        if (nv != p.value) pointers[n].value = nv;
        return;
      }
      if (saturated(op, p.value)) return;
      marks[n] = MARK_EXPAND;
      hits[i] = n;
      atomicAdd(counter, 1u);
      return;
    }
    if (d == target) {
      pointers[n].value = incoming;
      marks[n] = MARK_REDUCE;
      // Its subtree's range, for the scan that removes it whole.
      atomicAdd(removals[n], 1);
      atomicAdd(removals[subtreeEnd(n) - 1u], -1);
      atomicAdd(counter, 1u);
      atomicAdd(reduces, 1u);
      return;
    }
    n = uint(childTowards(cell, d) == 0 ? p.left : p.right);
  }
#else
  if (i >= nodes) return;
  Pointer p = pointers[i];
  if (isLeaf(p) || !collapsible(pointers[p.left], pointers[p.right])) return;
  marks[i] = MARK_COLLAPSE;
  atomicAdd(counter, 1u);
#endif
}
