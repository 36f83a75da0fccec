#version 450
// Page pass 1, a thread per active page: its message (message.comp) marks the pages it needs as
// requested this epoch, and lists each requested page that is inactive once (claimed) as new. A page
// that moved is marked moved. LevelSet::applyMessages is the host's twin.
layout(local_size_x = 64) in;
#include "page_state.glsl"
layout(std430, binding = 2) readonly buffer Messages { uint messages[]; };
layout(std430, binding = 7) readonly buffer ActiveList { int activeList[]; };
layout(std430, binding = 9) writeonly buffer NewList { int newList[]; };
uniform int movedOffset;

uint byteOf(int word, int i) { return (messages[word] >> (8u * uint(i & 3))) & 0xffu; }

void request(int page) {
  marks[3 * page] = epoch;
  if (pageTable[page] <= 1 && atomicExchange(marks[3 * page + 1], epoch) != epoch) newList[atomicAdd(newCount, 1)] = page;
}

void main() {
  int i = threadIndex();
  if (i >= activeCount) return;
  int page = activeList[i];
  uint m = byteOf(i >> 2, i);
  if (byteOf(movedOffset + (i >> 2), i) != 0u) marks[3 * page + 2] = epoch;
  ivec3 c = pageCoords(page);
  if ((m & 64u) != 0u) request(page);
  if ((m & 1u) != 0u && c.x + 1 < virtualPages.x) request(pageAt(c + ivec3(1, 0, 0)));
  if ((m & 2u) != 0u && c.x > 0) request(pageAt(c - ivec3(1, 0, 0)));
  if ((m & 4u) != 0u && c.y + 1 < virtualPages.y) request(pageAt(c + ivec3(0, 1, 0)));
  if ((m & 8u) != 0u && c.y > 0) request(pageAt(c - ivec3(0, 1, 0)));
  if ((m & 16u) != 0u && c.z + 1 < virtualPages.z) request(pageAt(c + ivec3(0, 0, 1)));
  if ((m & 32u) != 0u && c.z > 0) request(pageAt(c - ivec3(0, 0, 1)));
}
