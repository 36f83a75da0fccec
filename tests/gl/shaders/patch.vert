#version 450
// One patch per draw: the four corners of the unit square, from gl_VertexID.
out vec2 corner;
void main() { corner = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1); }
