// Shared by the marching-cubes passes: the field with its mirrored padding, the visited blocks and
// their storage, and the case table (built on the CPU, extract/marching_cubes.cpp). Mirrors the CPU's
// sample().
//
// The field is a dense buffer of the grid, or (FIELD_PAGES) phi where a level set's pages hold it
// (levelset/shaders/paged_phi.glsl).
//
// Storage follows the visited blocks, not the grid: blocks[] lists the visited blocks first
// (visitedBlocks of them), then the blocks that only hold corners of visited cells; blockSlot[] maps
// a block to its place in that list (-1: none). A cell or grid point c (numbered from -1) lies in
// block (c + 1) / BLOCK_SIZE at local (c + 1) % BLOCK_SIZE, and is stored at
// slot * BLOCK_SIZE^3 + local index.
#ifdef FIELD_PAGES
#include "levelset/shaders/paged_phi.glsl"
#else
layout(std430, binding = 0) readonly buffer Field { float field[]; };
#endif
layout(std430, binding = 1) readonly buffer Blocks { ivec4 blocks[]; };  // block coordinates
// Per case: offset into polygons[] and polygon count. A polygon: apex (or -1), corner count n, then
// n cell edges.
layout(std430, binding = 2) readonly buffer CaseIndex { ivec2 caseIndex[256]; };
layout(std430, binding = 3) readonly buffer Polygons { int polygons[]; };
layout(std430, binding = 11) readonly buffer BlockSlots { int blockSlot[]; };
uniform ivec3 dims;
uniform float iso;
uniform int visitedBlocks;
uniform ivec3 blockGrid;  // blocks along each axis in blockSlot[]

const int kEdgeCorner[24] = int[24](0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7);
const int kEdgeAxis[12] = int[12](0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2);
const int kBlockCells = BLOCK_SIZE * BLOCK_SIZE * BLOCK_SIZE;

float fieldAt(ivec3 c) {
#ifdef FIELD_PAGES
  return pagedPhi(c);
#else
  return field[(c.z * dims.y + c.y) * dims.x + c.x];
#endif
}

float sampleField(ivec3 p) {
  ivec3 c = clamp(p, ivec3(0), dims - 1);
  float v = fieldAt(c);
  if (c == p) return v;
  return v > iso ? 2.0 * iso - v : v;
}

int groupIndex() { return int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x); }

// The cell this invocation handles (its lower corner, from -1), or false when outside the grid.
bool cellOf(out ivec3 cell) {
  int b = groupIndex();
  if (b >= visitedBlocks) return false;
  cell = blocks[b].xyz * BLOCK_SIZE - 1 + ivec3(gl_LocalInvocationID);
  return all(lessThan(cell, dims));
}

ivec3 cornerOffset(int k) { return ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1); }

// Where a cell's or a grid point's values are stored (see above).
int storageIndex(ivec3 c) {
  ivec3 b = (c + 1) / BLOCK_SIZE, l = (c + 1) % BLOCK_SIZE;
  int slot = blockSlot[(b.z * blockGrid.y + b.y) * blockGrid.x + b.x];
  return slot * kBlockCells + (l.z * BLOCK_SIZE + l.y) * BLOCK_SIZE + l.x;
}
// The grid point stored at index i.
ivec3 pointAt(uint i) {
  int slot = int(i / uint(kBlockCells)), l = int(i % uint(kBlockCells));
  return blocks[slot].xyz * BLOCK_SIZE - 1 + ivec3(l % BLOCK_SIZE, (l / BLOCK_SIZE) % BLOCK_SIZE, l / (BLOCK_SIZE * BLOCK_SIZE));
}
