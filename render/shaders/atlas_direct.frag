#version 450
// The surface shaded straight from the evaluation stage, for frames without a wireframe.
#include "shading.glsl"
in vec3 tessWorld;
in vec3 tessNormal;
flat in uint tessChart;
out vec4 fragColour;
void main() { fragColour = vec4(shade(tessWorld, tessNormal, tessChart), 1.0); }
