// The active-page table the CPU uploads, and the apron of a page read through it. One work group
// per active page, P x P invocations; neighbours resolve through the table's physical origins, never
// through a dependent page-table read. Needs PAGE_SIZE defined and an r32f image2D `phi` declared
// before it is included.
struct PageEntry {
  ivec4 info;           // slot, page x, page y, page z
  ivec2 origins[27];    // physical texel origins of the 3x3x3 pages around; [13] is the page itself
};
layout(std430, binding = 0) readonly buffer Pages { PageEntry pages[]; };

// How many pages are active: a uniform the host sets, or (PAGES_ON_GPU 1, the passes gpu_page_chain.h
// runs between them) the first word of the page state the GPU keeps, page_state.glsl's.
#if PAGES_ON_GPU
layout(std430, binding = 5) readonly buffer ActivePageCount { int pageCount; };
#else
uniform int pageCount;
#endif
uniform ivec3 dims;

// (P+2) x (P+2) x 3 values around the page.
shared float apron[3][PAGE_SIZE + 2][PAGE_SIZE + 2];

int pageIndex() { return int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x); }

// Buffers of a byte per active page hold four pages to a uint: page's is at [page >> 2], this shift.
uint pageByteShift(int page) { return 8u * uint(page & 3); }

void loadApron(int page) {
  const int side = PAGE_SIZE + 2;
  for (int t = int(gl_LocalInvocationIndex); t < 3 * side * side; t += PAGE_SIZE * PAGE_SIZE) {
    int dz = t / (side * side), rest = t % (side * side);
    int lx = rest % side - 1, ly = rest / side - 1;
    int ox = lx < 0 ? -1 : (lx >= PAGE_SIZE ? 1 : 0), oy = ly < 0 ? -1 : (ly >= PAGE_SIZE ? 1 : 0);
    ivec2 origin = pages[page].origins[dz * 9 + (oy + 1) * 3 + (ox + 1)];
    apron[dz][ly + 1][lx + 1] = imageLoad(phi, origin + ivec2(lx - ox * PAGE_SIZE, ly - oy * PAGE_SIZE)).r;
  }
  barrier();
}

void neighbourhood(ivec2 local, out float u[27]) {
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) u[(dz + 1) * 9 + (dy + 1) * 3 + (dx + 1)] = apron[dz + 1][local.y + 1 + dy][local.x + 1 + dx];
}

ivec3 voxelOf(int page, ivec2 local) { return ivec3(pages[page].info.yz * PAGE_SIZE + local, pages[page].info.w); }
