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
uniform vec2 viewport;
out vec3 worldPosition;
out vec3 worldNormal;
noperspective out vec3 edgeDistance;
flat out ivec3 edgeOnTileBorder;
flat out uint chart;

bool onSameFaceSide(vec2 a, vec2 b) {
  return (a.x == 0.0 && b.x == 0.0) || (a.x == 1.0 && b.x == 1.0) || (a.y == 0.0 && b.y == 0.0) || (a.y == 1.0 && b.y == 1.0);
}

void main() {
  vec2 s[3];
  for (int i = 0; i < 3; ++i) s[i] = gl_in[i].gl_Position.xy / max(gl_in[i].gl_Position.w, 1e-6) * viewport * 0.5;
  float twiceArea = abs((s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y));
  ivec3 border;
  for (int i = 0; i < 3; ++i)
    border[i] = onSameFaceSide(inpt[(i + 1) % 3].v.patchCoord.xy, inpt[(i + 2) % 3].v.patchCoord.xy) ? 1 : 0;
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position;
    worldPosition = inpt[i].v.position.xyz;
    worldNormal = inpt[i].v.normal;
    edgeDistance = vec3(0.0);
    edgeDistance[i] = twiceArea / max(length(s[(i + 2) % 3] - s[(i + 1) % 3]), 1e-6);
    edgeOnTileBorder = border;
    chart = uint(inpt[i].v.patchCoord.w);
    EmitVertex();
  }
  EndPrimitive();
}
