#version 450
// One cube per inside leaf of a DVT (instanced over every node; the others are dropped here).
#include "dvt_tree.glsl"
uniform mat4 viewProjection;
out vec3 worldPosition;
flat out vec3 worldNormal;

void main() {
  uint node = uint(gl_InstanceID);
  Pointer p = pointers[node];
  if (!isLeaf(p) || p.value <= 0.0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the triangle is dropped
    return;
  }
  // Face f of the cube: axis f / 2 at its low (even f) or high side; two triangles of (u, v) corners.
  const vec2 corners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
  int f = gl_VertexID / 6, a = f / 2;
  vec2 uv = corners[gl_VertexID % 6];
  vec3 unit;
  unit[a] = float(f % 2);
  unit[(a + 1) % 3] = uv.x;
  unit[(a + 2) % 3] = uv.y;
  vec3 size;
  vec3 lo = cellLow(cells[node], size);
  vec4 world = indexToWorld * vec4(lo + unit * size, 1.0);
  vec3 n = vec3(0.0);
  n[a] = f % 2 == 0 ? -1.0 : 1.0;
  worldPosition = world.xyz;
  worldNormal = normalToWorld * n;
  gl_Position = viewProjection * world;
}
