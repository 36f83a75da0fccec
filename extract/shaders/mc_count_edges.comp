#version 450
// Between classify and the scan: each grid point's vertex count is the number of its used edges.
layout(local_size_x = 256) in;
layout(std430, binding = 6) readonly buffer EdgeBits { uint edgeBits[]; };
layout(std430, binding = 8) writeonly buffer EdgeOffset { uint edgeOffset[]; };
uniform uint pointCount;
void main() {
  uint i = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 256u) + gl_GlobalInvocationID.x;
  if (i < pointCount) edgeOffset[i] = uint(bitCount(edgeBits[i]));
}
