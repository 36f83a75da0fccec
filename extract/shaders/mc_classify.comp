#version 450
// Pass 1: each cell's triangle and centre-vertex counts, and the grid edges its polygons use.
layout(local_size_x = BLOCK_SIZE, local_size_y = BLOCK_SIZE, local_size_z = BLOCK_SIZE) in;
#include "marching.glsl"
layout(std430, binding = 4) buffer CellTriangles { uint cellTriangles[]; };
layout(std430, binding = 5) buffer CellCentres { uint cellCentres[]; };
layout(std430, binding = 6) buffer EdgeBits { uint edgeBits[]; };   // per grid point: bit = axis used
layout(std430, binding = 7) buffer VisitedCells { uint visited; };

void main() {
  ivec3 cell;
  if (!cellOf(cell)) return;
  atomicAdd(visited, 1u);
  int pattern = 0;
  for (int k = 0; k < 8; ++k) pattern |= (sampleField(cell + cornerOffset(k)) > iso ? 1 : 0) << k;
  if (pattern == 0 || pattern == 255) return;
  uint triangles = 0u, centres = 0u;
  int at = caseIndex[pattern].x;
  for (int p = 0; p < caseIndex[pattern].y; ++p) {
    int apex = polygons[at], n = polygons[at + 1];
    triangles += apex >= 0 ? uint(n - 2) : uint(n);
    centres += apex >= 0 ? 0u : 1u;
    for (int i = 0; i < n; ++i) {
      int e = polygons[at + 2 + i];
      ivec3 p0 = cell + cornerOffset(kEdgeCorner[2 * e]);
      atomicOr(edgeBits[storageIndex(p0)], 1u << kEdgeAxis[e]);
    }
    at += 2 + n;
  }
  cellTriangles[storageIndex(cell)] = triangles;
  cellCentres[storageIndex(cell)] = centres;
}
