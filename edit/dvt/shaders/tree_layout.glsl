// The DVT's streams as GLSL sees them (volume_tree.h): a node's pointers and its packed cell, for the
// tree's passes (tree_rules.glsl) and its renderers (render/shaders/dvt_*).
struct Pointer {
  int parent, left, right;
  float value;
};
struct InputVoxel {
  uint xy, zd;
  float value;
  uint unused;
};

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
// The depth of the deepest common ancestor of two cells of which neither contains the other.
uint commonDepth(uvec2 a, uvec2 b) {
  uint d = 0u;
  while (d < depthOf(a) && d < depthOf(b) && childTowards(a, d) == childTowards(b, d)) ++d;
  return d;
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

