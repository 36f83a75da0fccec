#version 450
// Pass 3: each cell writes its triangles at triangleOffset[cell]; polygons without an apex fan
// from a centre vertex numbered after every edge vertex, in cell order, drawn at the mean of its
// ring (as the CPU places it) with the ring's mean normal (DRAWN_VERTICES).
layout(local_size_x = BLOCK_SIZE, local_size_y = BLOCK_SIZE, local_size_z = BLOCK_SIZE) in;
#include "marching.glsl"
layout(std430, binding = 4) readonly buffer CellTriangles { uint triangleOffset[]; };
layout(std430, binding = 5) readonly buffer CellCentres { uint centreOffset[]; };
layout(std430, binding = 6) readonly buffer EdgeBits { uint edgeBits[]; };
layout(std430, binding = 8) readonly buffer EdgeOffset { uint edgeOffset[]; };
layout(std430, binding = 10) writeonly buffer Triangles { uint triangles[]; };
#if DRAWN_VERTICES
struct DrawnVertex { vec4 position; vec4 normal; };
layout(std430, binding = 12) buffer DrawnVertices { DrawnVertex drawn[]; };
#endif
uniform uint edgeVertexCount;

uint vertexOf(ivec3 cell, int e) {
  ivec3 p = cell + cornerOffset(kEdgeCorner[2 * e]);
  int point = storageIndex(p);
  uint below = edgeBits[point] & ((1u << kEdgeAxis[e]) - 1u);
  return edgeOffset[point] + uint(bitCount(below));
}

void main() {
  ivec3 cell;
  if (!cellOf(cell)) return;
  int pattern = 0;
  for (int k = 0; k < 8; ++k) pattern |= (sampleField(cell + cornerOffset(k)) > iso ? 1 : 0) << k;
  if (pattern == 0 || pattern == 255) return;
  uint out_ = triangleOffset[storageIndex(cell)] * 3u;
  uint centre = edgeVertexCount + centreOffset[storageIndex(cell)];
  int at = caseIndex[pattern].x;
  for (int p = 0; p < caseIndex[pattern].y; ++p) {
    int apex = polygons[at], n = polygons[at + 1];
    if (apex >= 0) {
      for (int i = 1; i + 1 < n; ++i) {
        triangles[out_++] = vertexOf(cell, polygons[at + 2 + apex]);
        triangles[out_++] = vertexOf(cell, polygons[at + 2 + (apex + i) % n]);
        triangles[out_++] = vertexOf(cell, polygons[at + 2 + (apex + i + 1) % n]);
      }
    } else {
#if DRAWN_VERTICES
      vec3 position = vec3(0.0), normal = vec3(0.0);
#endif
      for (int i = 0; i < n; ++i) {
        uint corner = vertexOf(cell, polygons[at + 2 + i]);
        triangles[out_++] = centre;
        triangles[out_++] = corner;
        triangles[out_++] = vertexOf(cell, polygons[at + 2 + (i + 1) % n]);
#if DRAWN_VERTICES
        position += drawn[corner].position.xyz;
        normal += drawn[corner].normal.xyz;
#endif
      }
#if DRAWN_VERTICES
      drawn[centre] = DrawnVertex(vec4(position / float(n), 1.0), vec4(length(normal) > 0.0 ? normalize(normal) : vec3(0.0), 0.0));
#endif
      ++centre;
    }
    at += 2 + n;
  }
}
