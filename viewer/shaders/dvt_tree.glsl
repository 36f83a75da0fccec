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

// A point on a split plane goes to the half `heading` points into (the upper one for heading >= 0): a
// ray along a plane, on it, must find the leaves it enters, not the ones it leaves.
Leaf leafToward(vec3 p, vec3 heading) {
  Leaf l = Leaf(0u, vec3(-0.5), vec3(exp2(float(voxelSplits))));
  for (uint d = 0u; !isLeaf(pointers[l.node]); ++d) {
    uint a = d % 3u;
    l.size[a] *= 0.5;
    float split = l.lo[a] + l.size[a];
    bool upper = p[a] > split || (p[a] == split && heading[a] >= 0.0);
    if (upper) l.lo[a] += l.size[a];
    l.node = uint(upper ? pointers[l.node].right : pointers[l.node].left);
  }
  return l;
}
Leaf leafAt(vec3 p) { return leafToward(p, vec3(1.0)); }

vec3 cellLow(uvec2 cell, out vec3 size) {
  uint depth = depthOf(cell);
  for (uint a = 0u; a < 3u; ++a) size[a] = exp2(float(voxelSplits) - float(splitsOf(a, depth)));
  return vec3(coordinate(cell, 0u), coordinate(cell, 1u), coordinate(cell, 2u)) * size - 0.5;
}
