#version 450
// Fills whole pages with one value each: newly activated pages start as the static page they were.
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
struct Fill { ivec2 origin; float value; float unused; };
layout(std430, binding = 3) readonly buffer Fills { Fill fills[]; };
layout(r32f, binding = 0) writeonly uniform image2D phi;
uniform int fillCount;
void main() {
  int i = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
  if (i >= fillCount) return;
  imageStore(phi, fills[i].origin + ivec2(gl_LocalInvocationID.xy), vec4(fills[i].value));
}
