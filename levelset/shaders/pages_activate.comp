#version 450
// Page pass 4, a work group per new page: it takes a slot from the free stack, starts as the static
// page it was (+-CLAMP in phi), gets the source's intensities there (0 past the volume's edge), and
// joins the active list after the kept pages, marked moved.
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
#include "page_state.glsl"
layout(std430, binding = 8) writeonly buffer NextList { int nextList[]; };
layout(std430, binding = 9) readonly buffer NewList { int newList[]; };
layout(std430, binding = 10) readonly buffer FreeStack { int freeStack[]; };
layout(std430, binding = 13) readonly buffer Source { float source[]; };  // the whole volume, x fastest
layout(r32f, binding = 0) writeonly uniform image2D phi;
layout(r32f, binding = 2) writeonly uniform image2D sourcePool;
uniform ivec3 dims;
shared int wasInside;

void main() {
  int j = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);
  if (j >= newCount) return;
  int page = newList[j];
  if (gl_LocalInvocationIndex == 0) wasInside = pageTable[page] == 1 ? 1 : 0;
  barrier();
  int slot = freeStack[freeTop - 1 - j];
  ivec2 local = ivec2(gl_LocalInvocationID.xy), texel = slotOrigin(slot) + local;
  imageStore(phi, texel, vec4(wasInside == 1 ? CLAMP : -CLAMP));
  ivec3 voxel = ivec3(pageCoords(page).xy * PAGE_SIZE + local, pageCoords(page).z);
  bool within = voxel.x < dims.x && voxel.y < dims.y;
  imageStore(sourcePool, texel, vec4(within ? source[(voxel.z * dims.y + voxel.y) * dims.x + voxel.x] : 0.0));
  if (gl_LocalInvocationIndex == 0) {
    pageTable[page] = slot;
    nextList[keptCount + j] = page;
    marks[3 * page + 2] = epoch;
  }
}
