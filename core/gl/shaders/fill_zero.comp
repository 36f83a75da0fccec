#version 450
// Zeroes the first `count` words of the buffer bound at FILL_BINDING (the context's last shader storage
// binding point, which no algorithm binds, so a fill disturbs none of its caller's bindings): four
// words an invocation, the last invocation's tail word by word.
layout(local_size_x = 256) in;
layout(std430, binding = FILL_BINDING) writeonly buffer Quads { uvec4 quads[]; };
layout(std430, binding = FILL_BINDING) writeonly buffer Words { uint words[]; };
uniform uint count;

void main() {
  uint quad = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationID.x;
  uint first = quad * 4u;
  if (first >= count) return;
  if (count - first >= 4u) {
    quads[quad] = uvec4(0u);
  } else {
    for (uint w = first; w < count; ++w) words[w] = 0u;
  }
}
