#version 450
// Pass 1: speed F and rate F|grad phi| at every voxel of every active page evaluated; max |F| over moving voxels.
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
layout(r32f, binding = 0) readonly uniform image2D phi;
#include "pages.glsl"
#include "speed.glsl"
#include "counters.glsl"
layout(r32f, binding = 1) writeonly uniform image2D rate;
layout(r32f, binding = 2) readonly uniform image2D source;  // the source's pages, beside phi's
// A byte per active page, four to a uint: 0 where the page is settled (level_set.h), its rate 0.
layout(std430, binding = 3) readonly buffer Evaluate { uint evaluate[]; };
uniform float target, width, alpha;
shared uint groupMax;

void main() {
  int page = pageIndex();
  if (page >= pageCount) return;
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  ivec2 texel = pages[page].origins[13] + local;
  if (((evaluate[page >> 2] >> pageByteShift(page)) & 0xffu) == 0u) {  // the whole group returns together
    imageStore(rate, texel, vec4(0.0));
    return;
  }
  if (gl_LocalInvocationIndex == 0) groupMax = 0u;
  loadApron(page);
  ivec3 voxel = voxelOf(page, local);
  float r = 0.0;
  if (voxel.x < dims.x && voxel.y < dims.y) {
    float u[27];
    neighbourhood(local, u);
    VoxelUpdate v = evaluateVoxel(u, imageLoad(source, texel).r, target, width, alpha);
    r = v.rate;
    if (r != 0.0) atomicMax(groupMax, floatBitsToUint(abs(v.speed)));
  }
  imageStore(rate, texel, vec4(r));
  barrier();
  if (gl_LocalInvocationIndex == 0) atomicMax(maxSpeedBits, groupMax);
}
