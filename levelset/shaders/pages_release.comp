#version 450
// Page pass 2, a thread per active page: one no page requested goes back to the static inside or
// outside page (its message's inside bit) and its slot onto the free stack; the others are kept, in
// nextList.
layout(local_size_x = 64) in;
#include "page_state.glsl"
layout(std430, binding = 2) readonly buffer Messages { uint messages[]; };
layout(std430, binding = 7) readonly buffer ActiveList { int activeList[]; };
layout(std430, binding = 8) writeonly buffer NextList { int nextList[]; };
layout(std430, binding = 10) buffer FreeStack { int freeStack[]; };

void main() {
  int i = threadIndex();
  if (i >= activeCount) return;
  int page = activeList[i];
  if (marks[3 * page] == epoch) {
    nextList[atomicAdd(keptCount, 1)] = page;
    return;
  }
  bool inside = ((messages[i >> 2] >> (8u * uint(i & 3))) & 128u) != 0u;
  freeStack[atomicAdd(freeTop, 1)] = pageTable[page];
  pageTable[page] = inside ? 1 : 0;
}
