#version 450
// The restructure pass (tree_passes.h): every kept node to its new index (the scanned remap stream),
// pointers remapped, expanded leaves followed by their two children (CpuTreePasses::writeNode).
layout(local_size_x = 64) in;
#include "tree_rules.glsl"
layout(std430, binding = 6) writeonly buffer NewPointers { Pointer newPointers[]; };
layout(std430, binding = 7) writeonly buffer NewCells { uvec2 newCells[]; };
uniform bool allowExpand;
uniform float childScales[MAX_DEPTH + 1];

void main() {
  uint n = threadIndex();
  if (n >= count || remap[n + 1u] == remap[n]) return;
  uint o = remap[n];
  Pointer p = pointers[n];
  uint m = marks[n];
  Pointer outp = Pointer(NONE, NONE, NONE, p.value);
  if (p.parent >= 0) outp.parent = int(remap[p.parent]);  // a kept node's parent is kept
  bool expand = m == MARK_EXPAND && allowExpand;
  if (m == MARK_COLLAPSE) outp.value = pointers[p.left].value;
  if (expand) {
    outp.left = int(o + 1u), outp.right = int(o + 2u);
  } else if (!isLeaf(p) && m != MARK_REDUCE && m != MARK_COLLAPSE) {
    outp.left = int(remap[p.left]), outp.right = int(remap[p.right]);
  }
  newPointers[o] = outp;
  uvec2 cell = cells[n];
  newCells[o] = cell;
  if (!expand) return;
  for (int k = 0; k < 2; ++k) {
    uint child = o + 1u + uint(k);
    newPointers[child] = Pointer(int(o), NONE, NONE, childValue(p.value, childScales[depthOf(cell)]));
    newCells[child] = childCell(cell, k);
  }
}
