#version 450
// OpenSubdiv's evaluated vertices shaded straight from its evaluation stage (world positions: the
// "model view" is the placement), when no wireframe asks for a geometry stage.
#include "shading.glsl"
struct OutputVertex {
  vec4 position;
  vec3 normal;
  vec3 tangent;
  vec3 bitangent;
  vec4 patchCoord;
  vec2 tessCoord;
};
in block { OutputVertex v; } inpt;
out vec4 fragColour;
void main() { fragColour = vec4(shade(inpt.v.position.xyz, inpt.v.normal, uint(inpt.v.patchCoord.w)), 1.0); }
