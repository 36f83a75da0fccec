// Shared by the marching-cubes passes: the field with its mirrored padding, cells in visited blocks,
// and the case table (built on the CPU, extract/marching_cubes.cpp). Mirrors the CPU's sample().
layout(std430, binding = 0) readonly buffer Field { float field[]; };
layout(std430, binding = 1) readonly buffer Blocks { ivec4 blocks[]; };   // visited block coordinates
// Per case: offset into polygons[] and polygon count. A polygon: apex (or -1), corner count n, then
// n cell edges.
layout(std430, binding = 2) readonly buffer CaseIndex { ivec2 caseIndex[256]; };
layout(std430, binding = 3) readonly buffer Polygons { int polygons[]; };
uniform ivec3 dims;
uniform float iso;
uniform int blockCount;

const int kEdgeCorner[24] = int[24](0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7);
const int kEdgeAxis[12] = int[12](0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2);

float sampleField(ivec3 p) {
  ivec3 c = clamp(p, ivec3(0), dims - 1);
  float v = field[(c.z * dims.y + c.y) * dims.x + c.x];
  if (c == p) return v;
  return v > iso ? 2.0 * iso - v : v;
}

// The cell this invocation handles (its lower corner, from -1), or false when outside the grid.
bool cellOf(out ivec3 cell) {
  int b = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
  if (b >= blockCount) return false;
  cell = blocks[b].xyz * BLOCK_SIZE - 1 + ivec3(gl_LocalInvocationID);
  return all(lessThan(cell, dims));
}

ivec3 cornerOffset(int k) { return ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1); }

// Cells and grid points are numbered from -1 on each axis.
int cellIndex(ivec3 c) { return ((c.z + 1) * (dims.y + 1) + (c.y + 1)) * (dims.x + 1) + (c.x + 1); }
int pointIndex(ivec3 p) { return ((p.z + 1) * (dims.y + 2) + (p.y + 1)) * (dims.x + 2) + (p.x + 1); }
