// The DVT passes' buffers and per-node rules, the GLSL twin of levelset/dvt/tree_rules.h.
// Constants come as defines from ruleDefines(), so the two cannot drift.
#include "tree_layout.glsl"

layout(std430, binding = 0) buffer Pointers { Pointer pointers[]; };
layout(std430, binding = 1) readonly buffer Cells { uvec2 cells[]; };
layout(std430, binding = 2) buffer Marks { uint marks[]; };
layout(std430, binding = 3) buffer Remap { uint remap[]; };
layout(std430, binding = 5) buffer Counter { uint counter; };

uniform uint count;  // the threads wanted: input voxels or nodes

uint threadIndex() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  return group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
}

float inputValue(uint op, float value) { return op == OP_UNION ? value : -value; }
float combined(uint op, float leaf, float incoming) { return op == OP_UNION ? max(leaf, incoming) : min(leaf, incoming); }
bool saturated(uint op, float leaf) { return op == OP_UNION ? leaf == INSIDE : leaf == OUTSIDE; }
float childValue(float parent, float scale) { return clamp(parent * scale, OUTSIDE, INSIDE); }
bool collapsible(Pointer left, Pointer right) {
  return isLeaf(left) && isLeaf(right) && left.value == right.value && (left.value == INSIDE || left.value == OUTSIDE);
}
