// The DVT streams and per-node rules, the GLSL twin of levelset/dvt/tree_rules.h and volume_tree.h.
// Constants come as defines from ruleDefines(), so the two cannot drift.
struct Pointer {
  int parent, left, right;
  float value;
};
struct InputVoxel {
  uint xy, zd;
  float value;
  uint unused;
};

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

bool isLeaf(Pointer p) { return p.left < 0; }
uint splitsOf(uint axis, uint depth) { return (depth + 2u - axis) / 3u; }
uint depthOf(uvec2 cell) { return cell.y >> 16; }
uint coordinate(uvec2 cell, uint axis) {
  return axis == 0u ? (cell.x & 0xffffu) : (axis == 1u ? (cell.x >> 16) : (cell.y & 0xffffu));
}
int childTowards(uvec2 cell, uint d) {
  uint axis = d % 3u;
  return int((coordinate(cell, axis) >> (splitsOf(axis, depthOf(cell)) - 1u - splitsOf(axis, d))) & 1u);
}
uvec2 childCell(uvec2 cell, int which) {
  uint axis = depthOf(cell) % 3u;
  uint c = 2u * coordinate(cell, axis) + uint(which);
  uvec2 child = cell;
  if (axis == 0u) child.x = (cell.x & 0xffff0000u) | c;
  else if (axis == 1u) child.x = (cell.x & 0xffffu) | (c << 16);
  else child.y = (cell.y & 0xffff0000u) | c;
  child.y += 1u << 16;
  return child;
}

float inputValue(uint op, float value) { return op == OP_UNION ? value : -value; }
float combined(uint op, float leaf, float incoming) { return op == OP_UNION ? max(leaf, incoming) : min(leaf, incoming); }
bool saturated(uint op, float leaf) { return op == OP_UNION ? leaf == INSIDE : leaf == OUTSIDE; }
float childValue(float parent, float scale) { return clamp(parent * scale, OUTSIDE, INSIDE); }
bool collapsible(Pointer left, Pointer right) {
  return isLeaf(left) && isLeaf(right) && left.value == right.value && (left.value == INSIDE || left.value == OUTSIDE);
}
