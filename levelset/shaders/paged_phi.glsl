// phi of a level set read where its pages hold it, for shaders outside the solver (extraction, volume
// rendering): the pool image through the page table, one slot per virtual page of PAGE_SIZE x
// PAGE_SIZE x 1 voxels, as PageManager lays them out (inactive pages map to the static outside and
// inside slots 0 and 1, which hold -clamp and +clamp). levelset/paged_phi_gpu.h binds what it reads:
// the pool at image unit POOL_BINDING, the page table at buffer PAGE_TABLE_BINDING (both 0 unless
// defined), poolPagesX and pagesXY (virtual pages along x and y).
#ifndef POOL_BINDING
#define POOL_BINDING 0
#endif
#ifndef PAGE_TABLE_BINDING
#define PAGE_TABLE_BINDING 0
#endif
layout(r32f, binding = POOL_BINDING) readonly uniform image2D pool;
layout(std430, binding = PAGE_TABLE_BINDING) readonly buffer PageTable { int pageSlots[]; };
uniform int poolPagesX;
uniform ivec2 pagesXY;

// The slot of the page holding voxel c (inside the volume).
int pageSlotOf(ivec3 c) { return pageSlots[(c.z * pagesXY.y + c.y / PAGE_SIZE) * pagesXY.x + c.x / PAGE_SIZE]; }

float pagedPhi(ivec3 c) {
  int slot = pageSlotOf(c);
  ivec2 origin = ivec2(slot % poolPagesX, slot / poolPagesX) * PAGE_SIZE;
  return imageLoad(pool, origin + c.xy % PAGE_SIZE).r;
}
