#version 450
// Two-sided Lambert with a headlight (as mesh.frag), coloured by one colour or by chart, with an
// optional wireframe: tile borders brown, the edges inside tiles blue (the paper's Fig. 8).
in vec3 worldPosition;
in vec3 worldNormal;
noperspective in vec3 edgeDistance;
flat in ivec3 edgeOnTileBorder;
flat in uint chart;
uniform vec3 eye;
uniform vec3 colour;
uniform int colourByChart;
uniform int wireframe;
out vec4 fragColour;

vec3 chartColour(uint c) {
  uint h = c * 2654435761u;
  return vec3(float((h >> 8) & 255u), float((h >> 16) & 255u), float((h >> 24) & 255u)) / 255.0 * 0.6 + 0.35;
}

void main() {
  vec3 n = normalize(worldNormal);
  vec3 toEye = normalize(eye - worldPosition);
  float facing = dot(n, toEye);
  float light = 0.15 + 0.75 * abs(facing) + 0.15 * max(dot(n, normalize(vec3(0.3, 0.5, 0.8))), 0.0);
  vec3 c = colourByChart != 0 ? chartColour(chart) : colour;
  if (facing < 0.0) c *= 0.35;
  c *= light;
  if (wireframe != 0) {
    int nearest = edgeDistance.x < edgeDistance.y ? (edgeDistance.x < edgeDistance.z ? 0 : 2) : (edgeDistance.y < edgeDistance.z ? 1 : 2);
    bool border = edgeOnTileBorder[nearest] != 0;
    float width = border ? 1.6 : 0.5;
    float ink = (border ? 1.0 : 0.7) * (1.0 - smoothstep(width - 0.5, width + 0.5, edgeDistance[nearest]));
    c = mix(c, border ? vec3(0.55, 0.27, 0.07) : vec3(0.1, 0.25, 0.85), ink);
  }
  fragColour = vec4(c, 1.0);
}
