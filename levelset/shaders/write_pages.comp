#version 450
// Writes whole pages from a buffer, one work group per page: page i's PAGE_SIZE^2 values (rows in
// order) go to the pool at origins[i]. One dispatch instead of one texture upload per page.
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
layout(std430, binding = 3) readonly buffer Origins { ivec2 origins[]; };
layout(std430, binding = 4) readonly buffer Values { float values[]; };
layout(r32f, binding = 0) writeonly uniform image2D pool;
uniform int pageCount;
void main() {
  int i = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
  if (i >= pageCount) return;
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  imageStore(pool, origins[i] + local, vec4(values[(i * PAGE_SIZE + local.y) * PAGE_SIZE + local.x]));
}
