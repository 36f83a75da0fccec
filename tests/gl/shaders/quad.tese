#version 450
layout(quads, equal_spacing, ccw) in;
in vec2 tcCorner[];
out vec3 uvw;  // captured by transform feedback
void main() {
  uvw = vec3(gl_TessCoord.xy, 1.0);
  gl_Position = vec4(gl_TessCoord.xy * 2.0 - 1.0, 0.0, 1.0);
}
