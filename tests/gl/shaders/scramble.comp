#version 450
// out[i] = scramble(in[i]) + i, for every i < count.
#include "common.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { uint values[]; } src;
layout(std430, binding = 1) writeonly buffer Out { uint values[]; } dst;
uniform uint count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < count) dst.values[i] = scramble(src.values[i]) + i + OFFSET;
}
