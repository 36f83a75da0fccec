#version 450
layout(vertices = 4) out;
in vec2 corner[];
out vec2 tcCorner[];
uniform float level;
void main() {
  tcCorner[gl_InvocationID] = corner[gl_InvocationID];
  if (gl_InvocationID == 0) {
    gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = gl_TessLevelOuter[3] = level;
    gl_TessLevelInner[0] = gl_TessLevelInner[1] = level;
  }
}
