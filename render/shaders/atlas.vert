#version 450
// One vertex per patch: the tessellation control stage reads the patch by its index.
out int vertexPatch;
void main() { vertexPatch = gl_VertexID; }
