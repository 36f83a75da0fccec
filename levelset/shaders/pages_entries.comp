#version 450
// Page pass 5, a work group per four pages of the next active list: each page's entry of the page
// table the solver's passes read (pages.glsl: slot, coordinates, the origins of the 27 pages around
// it), the list copied into place, and whether the next iteration evaluates it: some page of its
// 3 x 3 x 3 (in the volume) moved this epoch (LevelSet::pagesToEvaluate). The four pages' evaluate
// bytes make one word, written whole: passes queued after the chain stops leave it as it is.
layout(local_size_x = 128) in;
#include "page_state.glsl"
struct PageEntry {
  ivec4 info;
  ivec2 origins[27];
};
layout(std430, binding = 0) writeonly buffer Pages { PageEntry pages[]; };
layout(std430, binding = 3) writeonly buffer Evaluate { uint evaluate[]; };
layout(std430, binding = 7) writeonly buffer ActiveList { int activeList[]; };
layout(std430, binding = 8) readonly buffer NextList { int nextList[]; };
uniform int evaluateAll;  // settledChange 0: every page every iteration
shared uint woken;  // a bit per page of the four

void main() {
  int word = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
  uint t = gl_LocalInvocationIndex, k = t / 32u, n = t % 32u;
  int i = word * 4 + int(k);
  if (t == 0u) woken = 0u;
  barrier();
  if (i < activeCount) {
    int page = nextList[i];
    ivec3 c = pageCoords(page);
    if (n < 27u) {
      ivec3 q3 = c + ivec3(int(n % 3u) - 1, int(n / 3u % 3u) - 1, int(n / 9u) - 1);
      bool within = inVolume(q3);
      int q = within ? pageAt(q3) : 0;
      pages[i].origins[n] = slotOrigin(within ? pageTable[q] : 0);
      if (evaluateAll != 0 || (within && marks[3 * q + 2] == epoch)) atomicOr(woken, 1u << k);
    } else if (n == 27u) {
      pages[i].info = ivec4(pageTable[page], c);
      activeList[i] = page;
    }
  }
  barrier();
  if (t == 0u && word * 4 < activeCount) {
    uint bytes = 0u;
    for (uint b = 0u; b < 4u; ++b) bytes |= ((woken >> b) & 1u) << (8u * b);
    evaluate[word] = bytes;
  }
}
