#version 450
// Pass 3: one activation byte per active page from the new phi (bits as in levelset/speed.h):
// +x -x +y -y +z -z (a neighbour page is needed), self (a voxel differs from a face neighbour),
// inside. Four pages' bytes share one uint of the message buffer.
layout(local_size_x = PAGE_SIZE, local_size_y = PAGE_SIZE) in;
layout(r32f, binding = 0) readonly uniform image2D phi;
#include "pages.glsl"
layout(std430, binding = 2) buffer Messages { uint messages[]; };
shared uint groupBits;

void main() {
  int page = pageIndex();
  if (page >= pageCount) return;
  if (gl_LocalInvocationIndex == 0) groupBits = 0u;
  loadApron(page);
  ivec2 local = ivec2(gl_LocalInvocationID.xy);
  float u[27];
  neighbourhood(local, u);
  float c = u[13];
  bool px = u[14] != c, mx = u[12] != c, py = u[16] != c, my = u[10] != c, pz = u[22] != c, mz = u[4] != c;
  uint bits = 0u;
  if (px || mx || py || my || pz || mz) bits |= 64u;
  if (px && local.x == PAGE_SIZE - 1) bits |= 1u;
  if (mx && local.x == 0) bits |= 2u;
  if (py && local.y == PAGE_SIZE - 1) bits |= 4u;
  if (my && local.y == 0) bits |= 8u;
  if (pz) bits |= 16u;
  if (mz) bits |= 32u;
  if (local == ivec2(0) && c > 0.0) bits |= 128u;
  if (bits != 0u) atomicOr(groupBits, bits);
  barrier();
  if (gl_LocalInvocationIndex == 0 && groupBits != 0u) atomicOr(messages[page >> 2], groupBits << pageByteShift(page));
}
