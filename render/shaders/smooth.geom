#version 450
// OpenSubdiv's evaluated vertices (world positions: the "model view" is the placement) on to the
// fragment shader the atlas renderer uses, with the wireframe's distances; a base face's border
// is a tile's border. Transform feedback captures worldPosition.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
struct OutputVertex {
  vec4 position;
  vec3 normal;
  vec3 tangent;
  vec3 bitangent;
  vec4 patchCoord;
  vec2 tessCoord;
};
in block { OutputVertex v; } inpt[];
#include "wire.glsl"
out vec3 worldPosition;
out vec3 worldNormal;
noperspective out vec3 edgeDistance;
flat out ivec3 edgeOnTileBorder;
flat out uint chart;

void main() {
  vec3 h = cornerHeights();
  ivec3 border;
  for (int i = 0; i < 3; ++i)
    border[i] = onOneSide(inpt[(i + 1) % 3].v.patchCoord.xy, inpt[(i + 2) % 3].v.patchCoord.xy, 1.0) ? 1 : 0;
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position;
    worldPosition = inpt[i].v.position.xyz;
    worldNormal = inpt[i].v.normal;
    edgeDistance = vec3(0.0);
    edgeDistance[i] = h[i];
    edgeOnTileBorder = border;
    chart = uint(inpt[i].v.patchCoord.w);
    EmitVertex();
  }
  EndPrimitive();
}
