// The page manager's state on the GPU (levelset/gpu_page_chain.h mirrors it as PageState): counts,
// the free stack's top, the chain's flags, the dispatch grids the passes size for each other, and a
// log of the iterations the host reads every few of them. Binding 5; the first word is the active
// page count the solver's passes read (pages.glsl, PAGES_ON_GPU).
layout(std430, binding = 5) buffer PageState {
  int activeCount;  // pages in the active list (after `plan`: the next iteration's)
  int keptCount;    // this iteration's pages kept (release.comp appends them to nextList)
  int newCount;     // pages requested that were inactive (request.comp lists them)
  int freeTop;      // free slots on the stack
  int epoch;        // this iteration's mark in `marks` (request, claim, moved)
  int stalled;      // 1: the free stack holds fewer slots than newCount; the host grows the pool
  int stopped;      // 1: converged, or no page left; the passes after do nothing
  int iterations;   // iterations done in this run
  uint pageArgs[3];    // one work group per active page
  uint threadArgs[3];  // 64 active pages a work group
  uint newArgs[3];     // one work group per new page
  uint wordArgs[3];    // four active pages a work group (pages_entries.comp: a word of evaluate bytes)
  int activations, releases, peakActive, ringCount;
  int ring[RING_SIZE];  // sign changes of the last `window` iterations, for the convergence test
  ivec4 iterationLog[LOG_SIZE];  // per iteration (iterations % LOG_SIZE): sign changes, dt's bits, active pages, 0
};

// Per virtual page, three epochs: requested (a page wants it active), claimed (listed as new once),
// moved (its phi changed by more than settledChange, or it was activated).
layout(std430, binding = 6) buffer PageTable { int pageTable[]; };  // virtual page -> slot (0, 1: static)
layout(std430, binding = 12) buffer Marks { int marks[]; };

uniform ivec3 virtualPages;  // pages per axis: x, y, z

ivec3 pageCoords(int page) { return ivec3(page % virtualPages.x, (page / virtualPages.x) % virtualPages.y, page / (virtualPages.x * virtualPages.y)); }
int pageAt(ivec3 c) { return (c.z * virtualPages.y + c.y) * virtualPages.x + c.x; }
bool inVolume(ivec3 c) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, virtualPages)); }

// The texel origin of slot s in the pool (PageManager::slotOrigin; POOL_PAGES_X slots a row).
ivec2 slotOrigin(int s) { return ivec2((s % POOL_PAGES_X) * PAGE_SIZE, (s / POOL_PAGES_X) * PAGE_SIZE); }

uvec3 gridFor(int groups) {  // gl::dispatchGrid
  uint g = uint(groups);
  return uvec3(min(g, 65535u), (g + 65534u) / 65535u, g == 0u ? 0u : 1u);
}

int threadIndex() { return int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex); }
