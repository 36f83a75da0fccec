#version 450
// Exclusive prefix sums of uint values, in two entry points chosen by define:
//   SCAN_BLOCKS: each work group scans 2 * 512 values in place and writes its total to blockSums
//   otherwise: adds blockSums[group] to every value of the group (after blockSums were scanned)
// How many values: the uniform `count`, or with DEVICE_COUNT the word counts[countIndex] that an
// earlier pass wrote (the dispatch covers the most there can be; groups past the count stop at once),
// divided up by 1024 per level of the recursion (levelShift: 10 per level).
layout(local_size_x = 512) in;
layout(std430, binding = 0) buffer Values { uint values[]; };
layout(std430, binding = 1) buffer BlockSums { uint blockSums[]; };
shared uint temp[1024];
#ifdef DEVICE_COUNT
layout(std430, binding = 2) readonly buffer Counts { uint counts[]; };
uniform uint countIndex, levelShift;
uint valueCount() {
  uint c = counts[countIndex];
  return levelShift == 0u ? c : (c >> levelShift) + ((c & ((1u << levelShift) - 1u)) != 0u ? 1u : 0u);
}
#else
uniform uint count;
uint valueCount() { return count; }
#endif

void main() {
  uint n = valueCount();
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint base = group * 1024u, t = gl_LocalInvocationID.x;
  // The dispatch is a gx * gy grid, up to gx - 1 groups more than there are blocks: those stop here,
  // the whole group at once (so the barriers below stay uniform), before writing blockSums[group].
  if (base >= n) return;
#ifdef SCAN_BLOCKS
  uint a = base + 2u * t, b = a + 1u;
  temp[2u * t] = a < n ? values[a] : 0u;
  temp[2u * t + 1u] = b < n ? values[b] : 0u;
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
  if (a < n) values[a] = temp[2u * t];
  if (b < n) values[b] = temp[2u * t + 1u];
#else
  uint add = blockSums[group];
  for (uint i = t; i < 1024u; i += 512u)
    if (base + i < n) values[base + i] += add;
#endif
}
