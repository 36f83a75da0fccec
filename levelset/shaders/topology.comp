#version 450
// Pass 2b (--topology preserve), once per parity class of (x, y, z) mod 2: each voxel of the class
// whose step (update.comp left it in `proposal`) changes its side takes it where it is a simple point
// of the object as `next` holds it (simple_point.glsl), and is held on its side, HELD_OFF_FRONT from
// the front, where not. No two voxels of a class are neighbours, so none reads what another writes.
// The CPU twin is CpuSolver::changeSidesWhereSimple.
layout(r32f, binding = 0) readonly uniform image2D phi;  // before the step
#include "pages.glsl"
#include "counters.glsl"
#include "simple_point.glsl"
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
layout(r32f, binding = 1) readonly uniform image2D proposal;
layout(r32f, binding = 2) coherent uniform image2D next;
layout(std430, binding = 2) buffer Messages { uint messages[]; };
uniform float settledChange;
uniform int movedOffset, parity;

// The inside bits of the voxel's 3 x 3 x 3 in `next`, through the page's 27 neighbours; past the
// volume's edge is outside.
uint insideAround(int page, ivec2 local, ivec3 voxel) {
  uint inside = 0u;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 g = voxel + ivec3(dx, dy, dz);
        if (any(lessThan(g, ivec3(0))) || any(greaterThanEqual(g, dims))) continue;
        ivec2 l = local + ivec2(dx, dy);
        ivec2 o = ivec2(l.x < 0 ? -1 : (l.x >= PAGE_SIZE ? 1 : 0), l.y < 0 ? -1 : (l.y >= PAGE_SIZE ? 1 : 0));
        ivec2 origin = pages[page].origins[(dz + 1) * 9 + (o.y + 1) * 3 + (o.x + 1)];
        if (imageLoad(next, origin + l - o * PAGE_SIZE).r > 0.0) inside |= 1u << ((dz + 1) * 9 + (dy + 1) * 3 + dx + 1);
      }
  return inside;
}

void main() {
  int page = pageIndex();
  if (page >= pageCount) return;
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  ivec3 voxel = voxelOf(page, local);
  if (voxel.x >= dims.x || voxel.y >= dims.y || (voxel.x & 1) + 2 * (voxel.y & 1) + 4 * (voxel.z & 1) != parity) return;
  ivec2 texel = pages[page].origins[13] + local;
  float old = imageLoad(phi, texel).r, proposed = imageLoad(proposal, texel).r;
  if ((proposed > 0.0) == (old > 0.0)) return;
  float value = isSimplePoint(insideAround(page, local, voxel)) ? proposed : (old > 0.0 ? HELD_OFF_FRONT : -HELD_OFF_FRONT);
  imageStore(next, texel, vec4(value));
  if ((value > 0.0) != (old > 0.0)) atomicAdd(signChanges, 1);
  if (abs(value - old) > settledChange) atomicOr(messages[movedOffset + (page >> 2)], 1u << pageByteShift(page));
}
