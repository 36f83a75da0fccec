#version 450
// A patch's tessellation levels: outer levels from its border classes, inner from itself.
#include "atlas_common.glsl"
layout(vertices = 1) out;
in int vertexPatch[];
patch out uvec4 tessPatch;
void main() {
  uvec4 p = patches[vertexPatch[0]];
  tessPatch = p;
  float s = float(patchSide(p) * patchRatio(p));  // in the patch's texels
  // GL's quad edges: outer 0 is u = 0 (our side 3), 1 is v = 0 (side 0), 2 is u = 1 (side 1), 3 is v = 1 (side 2).
  gl_TessLevelOuter[1] = s / float(sideSpacing(p, 0));
  gl_TessLevelOuter[2] = s / float(sideSpacing(p, 1));
  gl_TessLevelOuter[3] = s / float(sideSpacing(p, 2));
  gl_TessLevelOuter[0] = s / float(sideSpacing(p, 3));
  float inner = s / float(innerSpacing(p));
  // A whole tile in one cell would be cut along a diagonal the driver picks; where the tile's other
  // diagonal is an edge of a neighbour too (a corner in only two tiles), the two would fold over each
  // other. Its centre, as CPU level 1 has it, leaves only the tile's sides.
  bool oneCell = gl_TessLevelOuter[0] == 1.0 && gl_TessLevelOuter[1] == 1.0 && gl_TessLevelOuter[2] == 1.0 &&
                 gl_TessLevelOuter[3] == 1.0;
  if (inner == 1.0 && oneCell && patchSide(p) == chartSize - 1u) inner = 2.0;
  gl_TessLevelInner[0] = inner;
  gl_TessLevelInner[1] = inner;
}
