// The DVT passes' buffers and per-node rules, the GLSL twin of edit/dvt/tree_rules.h.
// Constants come as defines from ruleDefines(), so the two cannot drift.
#include "tree_layout.glsl"

layout(std430, binding = 0) buffer Pointers { Pointer pointers[]; };
layout(std430, binding = 1) readonly buffer Cells { uvec2 cells[]; };
layout(std430, binding = 2) buffer Marks { uint marks[]; };
layout(std430, binding = 3) buffer Remap { uint remap[]; };
layout(std430, binding = 4) buffer Removals { int removals[]; };  // reduced subtrees' ranges (dvt_mark.comp)
// The passes' state (GpuTreePasses::State is its C++ twin).
//   counter: the pass's count; reduces: the mark pass's reduce marks; grown, grownWrapped: the plan
//   pass's new nodes under expanded leaves (32-bit, so a wrap is flagged: the remap scan's total would
//   wrap too); nodes: the tree's node count, the node passes' threads.
//   A chained write (dvt_chain.comp): running until its mark or plan finds nothing to do, or it stops
//   (stopped: STOP_CAPACITY when the streams must grow first, `needed` nodes; STOP_LIMIT past the node
//   limit); restructures it ran; the two scans' lengths (0 when it has stopped or with nothing to remove) and
//   the indirect dispatch grids over nodes + 1 and over the input (zero once it has stopped).
layout(std430, binding = 5) buffer State {
  uint counter, reduces, grown, grownWrapped;
  uint nodes, running, restructures, stopped;
  uint capacity, nodeLimit, inputCount, needed;
  uint remapScanCount, removalScanCount, unused0, unused1;
  uvec4 nodeGroups, inputGroups;
};
layout(std430, binding = 8) readonly buffer Input { InputVoxel inputs[]; };
layout(std430, binding = 9) buffer Hits { uint hits[]; };  // per input voxel: the leaf it expands, or NO_HIT
struct Expansion {
  uint size, begin, end, unused;  // an expanded leaf's new nodes, and its voxels [begin, end)
};
layout(std430, binding = 10) buffer Expansions { Expansion expansions[]; };
const uint NO_HIT = 0xffffffffu;

uvec2 inputCell(uint i) { return uvec2(inputs[i].xy, inputs[i].zd); }

uniform uint count;  // the input passes' threads: the input voxels
uniform uint op;     // the write's (OP_UNION or the subtraction)
uniform float childScales[MAX_DEPTH + 1];

uint threadIndex() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  return group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
}

float inputValue(uint op, float value) { return op == OP_UNION ? value : -value; }
float combined(uint op, float leaf, float incoming) { return op == OP_UNION ? max(leaf, incoming) : min(leaf, incoming); }
bool saturated(uint op, float leaf) { return op == OP_UNION ? leaf == INSIDE : leaf == OUTSIDE; }
float childValue(float parent, float scale) { return clamp(parent * scale, OUTSIDE, INSIDE); }
// The index just past n's subtree (CpuTreePasses::subtreeEnd).
uint subtreeEnd(uint n) {
  for (uint m = n; m != 0u;) {
    uint q = uint(pointers[m].parent);
    if (pointers[q].left == int(m)) return uint(pointers[q].right);
    m = q;
  }
  return nodes;
}

// The depth an expanded leaf's new subtree is cut at (tree_rules.h: expansionCut, EXPAND_LEVELS levels).
uint expansionCut(float leafValue, uint leafDepth) {
  uint last = min(leafDepth + EXPAND_LEVELS, uint(MAX_DEPTH));
  float v = leafValue;
  for (uint d = leafDepth; d < last; ++d) {
    v = childValue(v, childScales[d]);
    if (saturated(op, v)) return d + 1u;
  }
  return last;
}

bool collapsible(Pointer left, Pointer right) {
  return isLeaf(left) && isLeaf(right) && left.value == right.value && (left.value == INSIDE || left.value == OUTSIDE);
}
