#version 450
// The plan pass (tree_passes.h): per node how many nodes it becomes (CpuTreePasses::emitOf) into the
// remap stream, to be prefix-summed; counts the changes in `counter`.
layout(local_size_x = 64) in;
#include "tree_rules.glsl"
uniform bool allowExpand;

void main() {
  uint n = threadIndex();
  if (n >= nodes) return;
  Pointer p = pointers[n];
  uint m = marks[n];
  uint emit = 1u;
  bool change = false;
  if (removals[n] > 0 || (p.parent >= 0 && marks[p.parent] == MARK_COLLAPSE)) {  // below a reduced node, or collapsed
    emit = 0u, change = true;
  } else if (m == MARK_EXPAND) {
    if (allowExpand) {
      emit = 1u + expansions[n].size, change = true;
      const uint before = atomicAdd(grown, expansions[n].size);  // few nodes expand: little contention
      if (before + expansions[n].size < before) grownWrapped = 1u;
    }
  } else {
    change = m == MARK_REDUCE || m == MARK_COLLAPSE;
  }
  remap[n] = emit;
  if (change) atomicAdd(counter, 1u);
}
