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
uniform vec2 viewport;
uniform uint chartSize;
out vec3 worldPosition;
out vec3 worldNormal;
noperspective out vec3 edgeDistance;
flat out ivec3 edgeOnTileBorder;
flat out uint chart;

bool onSameTileSide(vec2 a, vec2 b) {
  float n = float(chartSize - 1u);
  return (a.x == 0.0 && b.x == 0.0) || (a.x == n && b.x == n) || (a.y == 0.0 && b.y == 0.0) || (a.y == n && b.y == n);
}

void main() {
  vec2 s[3];
  for (int i = 0; i < 3; ++i) s[i] = gl_in[i].gl_Position.xy / max(gl_in[i].gl_Position.w, 1e-6) * viewport * 0.5;
  float twiceArea = abs((s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y));
  float h[3];
  for (int i = 0; i < 3; ++i) h[i] = twiceArea / max(length(s[(i + 2) % 3] - s[(i + 1) % 3]), 1e-6);
  ivec3 border;
  for (int i = 0; i < 3; ++i) border[i] = onSameTileSide(tessTexel[(i + 1) % 3], tessTexel[(i + 2) % 3]) ? 1 : 0;
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
