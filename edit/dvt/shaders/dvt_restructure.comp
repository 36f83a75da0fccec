#version 450
// The restructure pass (tree_passes.h): every kept node to its new index (the scanned remap stream),
// pointers remapped, expanded leaves followed by their two children (CpuTreePasses::writeNode).
layout(local_size_x = 64) in;
#include "tree_rules.glsl"
layout(std430, binding = 6) writeonly buffer NewPointers { Pointer newPointers[]; };
layout(std430, binding = 7) writeonly buffer NewCells { uvec2 newCells[]; };
uniform bool allowExpand;

// The first voxel of [a, b) (all inside `cell`, in pre-order) in the cell's upper half.
uint splitOf(uvec2 cell, uint a, uint b) {
  while (a < b) {
    uint m = a + (b - a) / 2u;
    if (childTowards(inputCell(m), depthOf(cell)) == 0) a = m + 1u;
    else b = m;
  }
  return a;
}

// The subtree an expanded leaf at new index o grows (CpuTreePasses::generate): depth first, each
// node split where voxels lie strictly inside it, new nodes in pre-order after o, values from the
// leaf's with one child scale per level; nodes at the cut (expansionCut) stay leaves. A node's
// record is written once, whole, when its children are known; the stack is an array per field.
void generate(uint o, Pointer leaf, uvec2 root, Expansion e) {
  float chain[MAX_DEPTH + 2];
  uint rootDepth = depthOf(root);
  chain[rootDepth] = leaf.value;
  for (uint d = rootDepth; d <= uint(MAX_DEPTH); ++d) chain[d + 1u] = childValue(chain[d], childScales[d]);
  const int depth = int(EXPAND_LEVELS) + 1;
  int parentOf[depth], leftOf[depth], rightOf[depth], nextOf[depth];
  uvec2 cellOf[depth];
  uint nodeOf[depth], beginOf[depth], splitAt[depth], endOf[depth];
  uint cut = expansionCut(leaf.value, rootDepth);
  int top = 0;
  parentOf[0] = leaf.parent, leftOf[0] = NONE, rightOf[0] = NONE, nextOf[0] = 0;
  cellOf[0] = root, nodeOf[0] = o, beginOf[0] = e.begin, splitAt[0] = splitOf(root, e.begin, e.end), endOf[0] = e.end;
  uint at = o + 1u;
  // At most two steps per new node (make it, finish it).
  for (uint step = 0u; step < 2u * e.size + 2u && top >= 0; ++step) {
    int k = nextOf[top];
    if (k == 2) {
      newPointers[nodeOf[top]] = Pointer(parentOf[top], leftOf[top], rightOf[top], chain[depthOf(cellOf[top])]);
      --top;
    } else {
      nextOf[top] = k + 1;
      uvec2 child = childCell(cellOf[top], k);
      uint a = k == 0 ? beginOf[top] : splitAt[top], b = k == 0 ? splitAt[top] : endOf[top];
      uint q = at++;
      if (k == 0) leftOf[top] = int(q);
      else rightOf[top] = int(q);
      newCells[q] = child;
      if (a < b && depthOf(child) < cut && !(b - a == 1u && inputCell(a) == child)) {
        int parent = int(nodeOf[top]);
        ++top;
        parentOf[top] = parent, leftOf[top] = NONE, rightOf[top] = NONE, nextOf[top] = 0;
        cellOf[top] = child, nodeOf[top] = q, beginOf[top] = a, splitAt[top] = splitOf(child, a, b), endOf[top] = b;
      } else {
        newPointers[q] = Pointer(int(nodeOf[top]), NONE, NONE, chain[depthOf(child)]);
      }
    }
  }
}

void main() {
  uint n = threadIndex();
  if (n >= nodes || remap[n + 1u] == remap[n]) return;
  uint o = remap[n];
  Pointer p = pointers[n];
  uint m = marks[n];
  Pointer outp = Pointer(NONE, NONE, NONE, p.value);
  if (p.parent >= 0) outp.parent = int(remap[p.parent]);  // a kept node's parent is kept
  bool expand = m == MARK_EXPAND && allowExpand;
  if (m == MARK_COLLAPSE) outp.value = pointers[p.left].value;
  uvec2 cell = cells[n];
  newCells[o] = cell;
  if (expand) {
    generate(o, outp, cell, expansions[n]);
    return;
  }
  if (!isLeaf(p) && m != MARK_REDUCE && m != MARK_COLLAPSE) outp.left = int(remap[p.left]), outp.right = int(remap[p.right]);
  newPointers[o] = outp;
}
