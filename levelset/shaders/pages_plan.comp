#version 450
// Page pass 3, one thread: whether the free stack holds a slot for every new page (else the chain
// stalls, every pass after it doing nothing, until the host grows the pool), and the grids of the
// passes that follow, for the next active list: the kept pages, then the new ones.
layout(local_size_x = 1) in;
#include "page_state.glsl"

void main() {
  if (stalled != 0 || stopped != 0) return;
  if (newCount > freeTop) {
    stalled = 1;
    pageArgs = uint[3](0u, 0u, 0u);
    threadArgs = uint[3](0u, 0u, 0u);
    newArgs = uint[3](0u, 0u, 0u);
    wordArgs = uint[3](0u, 0u, 0u);
    return;
  }
  releases += activeCount - keptCount;
  activeCount = keptCount + newCount;
  uvec3 g = gridFor(newCount);
  newArgs = uint[3](g.x, g.y, g.z);
  g = gridFor(activeCount);
  pageArgs = uint[3](g.x, g.y, g.z);
  g = gridFor((activeCount + 63) / 64);
  threadArgs = uint[3](g.x, g.y, g.z);
  g = gridFor((activeCount + 3) / 4);
  wordArgs = uint[3](g.x, g.y, g.z);
}
