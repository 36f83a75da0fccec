// A DVT's streams for the renderers (viewer/dvt_render), read only, and the walk to the leaf at a
// point in voxel index coordinates (a point on a split plane belongs to the upper half, as
// dvt::sampleAt says).
#include "edit/dvt/shaders/tree_layout.glsl"

layout(std430, binding = 0) readonly buffer Pointers { Pointer pointers[]; };
layout(std430, binding = 1) readonly buffer Cells { uvec2 cells[]; };

uniform mat4 indexToWorld;
uniform mat3 normalToWorld;  // index-space gradients to world normals: the inverse transpose
uniform int voxelSplits;

struct Leaf {
  uint node;
  vec3 lo, size;  // the leaf's box in index coordinates
};

Leaf rootLeaf() { return Leaf(0u, vec3(-0.5), vec3(exp2(float(voxelSplits)))); }

// Node l at depth d splits axis d % 3: splitOf halves l's box on that axis and returns the split's
// place; enterHalf then moves l to its child on the upper side (or the lower).
float splitOf(inout Leaf l, uint d) {
  l.size[d % 3u] *= 0.5;
  return l.lo[d % 3u] + l.size[d % 3u];
}
void enterHalf(inout Leaf l, uint d, bool upper) {
  if (upper) l.lo[d % 3u] += l.size[d % 3u];
  l.node = uint(upper ? pointers[l.node].right : pointers[l.node].left);
}

// The leaf at p below node l (at depth d). A point on a split plane goes to the half `heading` points
// into (the upper one for heading >= 0): a ray along a plane, on it, must find the leaves it enters,
// not the ones it leaves.
Leaf leafBelow(Leaf l, uint d, vec3 p, vec3 heading) {
  for (; !isLeaf(pointers[l.node]); ++d) {
    float split = splitOf(l, d);
    uint a = d % 3u;
    enterHalf(l, d, p[a] > split || (p[a] == split && heading[a] >= 0.0));
  }
  return l;
}
Leaf leafToward(vec3 p, vec3 heading) { return leafBelow(rootLeaf(), 0u, p, heading); }

// The leaves at the eight corners of a box, lo to hi (corner i takes hi on axis a where bit a of i
// is set), each the one leafToward(corner, +1) gives: the corners walk the tree together down to the
// node whose split falls between them, then each on alone. nodes[i]: corner i's leaf.
void cornerLeaves(vec3 lo, vec3 hi, out uint nodes[8]) {
  Leaf above = rootLeaf();
  uint d = 0u;
  for (; !isLeaf(pointers[above.node]); ++d) {
    Leaf child = above;
    float split = splitOf(child, d);
    uint a = d % 3u;
    bool upper = lo[a] >= split;
    if (!upper && hi[a] >= split) break;  // the corners part here
    above = child;
    enterHalf(above, d, upper);
  }
  for (int i = 0; i < 8; ++i) {
    vec3 p = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
    nodes[i] = leafBelow(above, d, p, vec3(1.0)).node;
  }
}

vec3 cellLow(uvec2 cell, out vec3 size) {
  uint depth = depthOf(cell);
  for (uint a = 0u; a < 3u; ++a) size[a] = exp2(float(voxelSplits) - float(splitsOf(a, depth)));
  return vec3(coordinate(cell, 0u), coordinate(cell, 1u), coordinate(cell, 2u)) * size - 0.5;
}
