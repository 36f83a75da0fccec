#version 450
#include "shading.glsl"
in vec3 worldPosition;
flat in vec3 worldNormal;
out vec4 fragColour;

void main() { fragColour = vec4(shade(worldPosition, worldNormal, 0u), 1.0); }
