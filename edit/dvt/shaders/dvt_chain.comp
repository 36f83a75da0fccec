#version 450
// The steps of a chained write (GpuTreePasses::writeChained) between the passes of tree_passes.h, so
// that the host reads nothing back until the write has ended. One entry point per define:
//   BEGIN      (one thread) an iteration's counters zeroed and its dispatch grids sized from `nodes`
//              and the input; all zero once the chain has stopped, so its later passes are empty
//   CLEAR      (per node and one past) the marks, remap, removals and expansions the passes read
//   GATE_MARK  (one thread, after the mark) ends the chain when nothing was marked; sizes the removal
//              scan (only when a subtree is reduced)
//   GATE_PLAN  (one thread, after the plan and its scan) ends the chain when nothing changes; stops it
//              before a restructure that would pass the node limit (STOP_LIMIT: the caller's own
//              iterations decide, exactly) or the streams' capacity (STOP_CAPACITY: they grow first)
//   END        (one thread, after the restructure) the new node count: the remap scan's total
layout(local_size_x = 64) in;
#include "tree_rules.glsl"

uvec4 grid(uint groups) { return uvec4(min(groups, 65535u), (groups + 65534u) / 65535u, 1u, 0u); }

void stop() {
  running = 0u;
  nodeGroups = uvec4(0u, 1u, 1u, 0u);
  inputGroups = uvec4(0u, 1u, 1u, 0u);
  remapScanCount = 0u;
  removalScanCount = 0u;
}

void main() {
#ifdef CLEAR
  uint n = threadIndex();
  if (n > nodes) return;
  remap[n] = 0u;
  removals[n] = 0;
  if (n == nodes) return;
  marks[n] = 0u;
  expansions[n] = Expansion(0u, 0u, 0u, 0u);
#else
  if (gl_GlobalInvocationID.x != 0u) return;  // the steps run on one thread
#endif
#if defined(BEGIN)
  counter = 0u, reduces = 0u, grown = 0u, grownWrapped = 0u;
  if (running == 0u) {
    stop();
    return;
  }
  nodeGroups = grid((nodes + 1u + 63u) / 64u);
  inputGroups = grid((inputCount + 63u) / 64u);
  remapScanCount = nodes + 1u;
  removalScanCount = 0u;
#elif defined(GATE_MARK)
  if (running == 0u) return;
  if (counter == 0u) {
    stop();
    return;
  }
  removalScanCount = reduces > 0u ? nodes + 1u : 0u;
  counter = 0u;
#elif defined(GATE_PLAN)
  if (running == 0u) return;
  if (counter == 0u) {
    stop();
    return;
  }
  uint total = remap[nodes];
  // As the host-driven plan rules (a total that 32 bits could wrap is over any limit), so that the
  // caller's iterations, which then finish the write, decide as they would have.
  if (grownWrapped != 0u || grown > MAX_TREE_NODES - nodes || total > nodeLimit) {
    stopped = STOP_LIMIT;
    stop();
  } else if (total > capacity) {
    stopped = STOP_CAPACITY;
    needed = total;
    stop();
  }
#elif defined(END)
  if (running == 0u) return;
  nodes = remap[nodes];
  ++restructures;
#endif
}
