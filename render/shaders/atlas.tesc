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
  gl_TessLevelInner[0] = inner;
  gl_TessLevelInner[1] = inner;
}
