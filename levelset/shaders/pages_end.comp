#version 450
// Page pass 6, one thread: the iteration's end. The new pages' slots leave the free stack, the
// iteration is logged for the host, the counters start again, and the chain stops where the host's
// run would (LevelSet::run: no page left, or converged over the window, windowConverged's test in
// doubles).
layout(local_size_x = 1) in;
#include "page_state.glsl"
#include "counters.glsl"
uniform int window, untilConverged, pageArea;
uniform double changedVoxels, changedShare;

void main() {
  if (stalled != 0 || stopped != 0) return;
  freeTop -= newCount;
  activations += newCount;
  peakActive = max(peakActive, activeCount);
  iterationLog[iterations % LOG_SIZE] = ivec4(signChanges, floatBitsToInt(dt), activeCount, 0);
  ring[ringCount % window] = signChanges;
  ++ringCount;
  ++iterations;
  bool done = activeCount == 0;
  if (!done && untilConverged != 0 && ringCount >= window) {
    int changes = 0;
    for (int k = 0; k < window; ++k) changes += ring[k];
    done = double(changes) < max(changedVoxels, changedShare * (double(activeCount) * double(pageArea)));
  }
  if (done) {
    stopped = 1;
    pageArgs = uint[3](0u, 0u, 0u);
    threadArgs = uint[3](0u, 0u, 0u);
    newArgs = uint[3](0u, 0u, 0u);
    wordArgs = uint[3](0u, 0u, 0u);
  }
  maxSpeedBits = 0u;
  signChanges = 0;
  dt = 0.0;
  keptCount = 0;
  newCount = 0;
  ++epoch;
}
