// A DVT's streams for the renderers (viewer/dvt_render), read only, and the walk to the leaf at a
// point in voxel index coordinates (a point on a split plane belongs to the upper half, as
// dvt::sampleAt says).
#include "levelset/dvt/shaders/tree_layout.glsl"

layout(std430, binding = 0) readonly buffer Pointers { Pointer pointers[]; };
layout(std430, binding = 1) readonly buffer Cells { uvec2 cells[]; };

uniform mat4 indexToWorld;
uniform mat3 normalToWorld;  // index-space gradients to world normals: the inverse transpose
uniform int voxelSplits;

struct Leaf {
  uint node;
  vec3 lo, size;  // the leaf's box in index coordinates
};

Leaf leafAt(vec3 p) {
  Leaf l = Leaf(0u, vec3(-0.5), vec3(exp2(float(voxelSplits))));
  for (uint d = 0u; !isLeaf(pointers[l.node]); ++d) {
    uint a = d % 3u;
    l.size[a] *= 0.5;
    bool upper = p[a] >= l.lo[a] + l.size[a];
    if (upper) l.lo[a] += l.size[a];
    l.node = uint(upper ? pointers[l.node].right : pointers[l.node].left);
  }
  return l;
}

vec3 cellLow(uvec2 cell, out vec3 size) {
  uint depth = depthOf(cell);
  for (uint a = 0u; a < 3u; ++a) size[a] = exp2(float(voxelSplits) - float(splitsOf(a, depth)));
  return vec3(coordinate(cell, 0u), coordinate(cell, 1u), coordinate(cell, 2u)) * size - 0.5;
}
