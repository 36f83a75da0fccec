#include "core/distance/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

namespace isoatlas {
namespace {

// The low 21 bits of x, two zero bits after each.
std::uint64_t spreadBits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

std::vector<MortonKey> mortonOrder(std::size_t count, const std::function<Vec3(std::size_t)>& at) {
  std::vector<MortonKey> keys(count);
  if (count == 0) return keys;
  Vec3 lo = at(0), hi = lo;
  for (std::size_t i = 1; i < count; ++i) {
    const Vec3 p = at(i);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double scale = double((1u << 21) - 1) / std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Vec3 c = (at(i) - lo) * scale;
      keys[i] = {spreadBits(std::uint64_t(c.x)) | spreadBits(std::uint64_t(c.y)) << 1 | spreadBits(std::uint64_t(c.z)) << 2,
                 std::uint32_t(i)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end(),
                     [](const MortonKey& a, const MortonKey& b) { return a.code != b.code ? a.code < b.code : a.index < b.index; });
  return keys;
}

}  // namespace isoatlas
