#version 450
// Pass 2: explicit Euler step of every active voxel into the other phi image, clamped; sign changes;
// a byte per page after the messages', set where a voxel changed by more than settledChange.
// PRESERVE_TOPOLOGY 1: a voxel whose step would change its side keeps its value here, and the step's
// value of every voxel goes into `rate` for topology.comp, which changes sides where that is simple.
layout(r32f, binding = 0) readonly uniform image2D phi;
#include "pages.glsl"
#include "speed.glsl"
#include "counters.glsl"
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
#if PRESERVE_TOPOLOGY
layout(r32f, binding = 1) uniform image2D rate;
#else
layout(r32f, binding = 1) readonly uniform image2D rate;
#endif
layout(r32f, binding = 2) writeonly uniform image2D next;
layout(std430, binding = 2) buffer Messages { uint messages[]; };
uniform float alpha, settledChange;
uniform int movedOffset;  // where the moved bytes start in `messages`, in uints
shared int groupChanges;
shared uint groupMoved;

void main() {
  int page = pageIndex();
  if (page >= pageCount) return;
  if (gl_LocalInvocationIndex == 0) groupChanges = 0, groupMoved = 0u;
  barrier();
  float step = timeStep(uintBitsToFloat(maxSpeedBits), alpha);
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  ivec3 voxel = voxelOf(page, local);
  ivec2 texel = pages[page].origins[13] + local;
  float old = imageLoad(phi, texel).r;
  // Voxels past the volume's edge (in partial pages) stay outside: the volume is padded with outside.
  float value = (voxel.x >= dims.x || voxel.y >= dims.y) ? -kClamp
                                                         : clamp(old + step * imageLoad(rate, texel).r, -kClamp, kClamp);
#if PRESERVE_TOPOLOGY
  imageStore(rate, texel, vec4(value));
  if ((value > 0.0) != (old > 0.0) && voxel.x < dims.x && voxel.y < dims.y) value = old;  // topology.comp decides
#endif
  imageStore(next, texel, vec4(value));
  if ((value > 0.0) != (old > 0.0)) atomicAdd(groupChanges, 1);
  if (abs(value - old) > settledChange) atomicOr(groupMoved, 1u);
  barrier();
  if (gl_LocalInvocationIndex == 0) {
    if (groupChanges != 0) atomicAdd(signChanges, groupChanges);
    if (groupMoved != 0u) atomicOr(messages[movedOffset + (page >> 2)], 1u << pageByteShift(page));
    if (page == 0) dt = step;  // one writer for the step the CPU reports
  }
}
