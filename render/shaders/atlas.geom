#version 450
// Passes the triangles on (transform feedback captures worldPosition) with, for the wireframe,
// each fragment's distance in pixels to the triangle's three edges and whether each edge lies on a
// tile's border.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 tessWorld[];
in vec3 tessNormal[];
in vec2 tessTexel[];
flat in uint tessChart[];
#include "wire.glsl"
uniform uint chartSize;
out vec3 worldPosition;
out vec3 worldNormal;
noperspective out vec3 edgeDistance;
flat out ivec3 edgeOnTileBorder;
flat out uint chart;

void main() {
  vec3 h = cornerHeights();
  ivec3 border;
  for (int i = 0; i < 3; ++i) border[i] = onOneSide(tessTexel[(i + 1) % 3], tessTexel[(i + 2) % 3], float(chartSize - 1u)) ? 1 : 0;
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position;
    worldPosition = tessWorld[i];
    worldNormal = tessNormal[i];
    edgeDistance = vec3(0.0);
    edgeDistance[i] = h[i];
    edgeOnTileBorder = border;
    chart = tessChart[i];
    EmitVertex();
  }
  EndPrimitive();
}
