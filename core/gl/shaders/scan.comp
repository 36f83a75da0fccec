#version 450
// Exclusive prefix sums of uint values, in two entry points chosen by define:
//   SCAN_BLOCKS: each work group scans 2 * 512 values in place and writes its total to blockSums
//   otherwise: adds blockSums[group] to every value of the group (after blockSums were scanned)
layout(local_size_x = 512) in;
layout(std430, binding = 0) buffer Values { uint values[]; };
layout(std430, binding = 1) buffer BlockSums { uint blockSums[]; };
uniform uint count;
shared uint temp[1024];

void main() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint base = group * 1024u, t = gl_LocalInvocationID.x;
  // The dispatch is a gx * gy grid, up to gx - 1 groups more than there are blocks: those stop here,
  // the whole group at once (so the barriers below stay uniform), before writing blockSums[group].
  if (base >= count) return;
#ifdef SCAN_BLOCKS
  uint a = base + 2u * t, b = a + 1u;
  temp[2u * t] = a < count ? values[a] : 0u;
  temp[2u * t + 1u] = b < count ? values[b] : 0u;
  // Up-sweep and down-sweep (Blelloch) in shared memory.
  uint offset = 1u;
  for (uint d = 512u; d > 0u; d >>= 1) {
    barrier();
    if (t < d) {
      uint ai = offset * (2u * t + 1u) - 1u, bi = offset * (2u * t + 2u) - 1u;
      temp[bi] += temp[ai];
    }
    offset <<= 1;
  }
  if (t == 0u) {
    blockSums[group] = temp[1023];
    temp[1023] = 0u;
  }
  for (uint d = 1u; d < 1024u; d <<= 1) {
    offset >>= 1;
    barrier();
    if (t < d) {
      uint ai = offset * (2u * t + 1u) - 1u, bi = offset * (2u * t + 2u) - 1u;
      uint x = temp[ai];
      temp[ai] = temp[bi];
      temp[bi] += x;
    }
  }
  barrier();
  if (a < count) values[a] = temp[2u * t];
  if (b < count) values[b] = temp[2u * t + 1u];
#else
  uint add = blockSums[group];
  for (uint i = t; i < 1024u; i += 512u)
    if (base + i < count) values[base + i] += add;
#endif
}
