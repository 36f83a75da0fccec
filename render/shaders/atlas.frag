#version 450
// The surface shaded (shading.glsl) with an optional wireframe: tile borders brown, the edges
// inside tiles blue (the paper's Fig. 8), from the geometry stage's distances to the edges.
#include "shading.glsl"
in vec3 worldPosition;
in vec3 worldNormal;
noperspective in vec3 edgeDistance;
flat in ivec3 edgeOnTileBorder;
flat in uint chart;
uniform int wireframe;
out vec4 fragColour;

void main() {
  vec3 c = shade(worldPosition, worldNormal, chart);
  if (wireframe != 0) {
    int nearest = edgeDistance.x < edgeDistance.y ? (edgeDistance.x < edgeDistance.z ? 0 : 2) : (edgeDistance.y < edgeDistance.z ? 1 : 2);
    bool border = edgeOnTileBorder[nearest] != 0;
    float width = border ? 1.6 : 0.5;
    float ink = (border ? 1.0 : 0.7) * (1.0 - smoothstep(width - 0.5, width + 0.5, edgeDistance[nearest]));
    c = mix(c, border ? vec3(0.55, 0.27, 0.07) : vec3(0.1, 0.25, 0.85), ink);
  }
  fragColour = vec4(c, 1.0);
}
