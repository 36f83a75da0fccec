#include "core/distance/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>

namespace isoatlas {
namespace {

// The low 10 bits of x, two zero bits after each.
std::uint32_t spreadBits(std::uint32_t x) {
  x &= 0x3ff;
  x = (x | x << 16) & 0x30000ff;
  x = (x | x << 8) & 0x300f00f;
  x = (x | x << 4) & 0x30c30c3;
  x = (x | x << 2) & 0x9249249;
  return x;
}

struct Bounds {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
};

// Sorts keys by their code (the high 32 bits, of which 30 are used), keeping the order of keys with
// equal codes: four passes of a byte each (least significant first), linear in the keys.
void radixSortByCode(std::vector<std::uint64_t>& keys) {
  std::vector<std::uint64_t> other(keys.size());
  for (int shift = 32; shift < 62; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (const std::uint64_t k : keys) ++start[((k >> shift) & 0xff) + 1];
    for (int d = 0; d < 256; ++d) start[d + 1] += start[d];
    for (const std::uint64_t k : keys) other[start[(k >> shift) & 0xff]++] = k;
    keys.swap(other);
  }
}

}  // namespace

std::vector<std::uint64_t> mortonOrder(std::size_t count, const std::function<Vec3(std::size_t)>& at) {
  const Bounds box = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count), Bounds{},
      [&](const tbb::blocked_range<std::size_t>& r, Bounds b) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) b.add(at(i));
        return b;
      },
      [](Bounds a, const Bounds& b) {
        a.add(b.lo), a.add(b.hi);
        return a;
      });
  const double scale = 1023.0 / std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z, 1e-300});
  std::vector<std::uint64_t> keys(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Vec3 c = (at(i) - box.lo) * scale;
      const std::uint32_t code = spreadBits(std::uint32_t(c.x)) | spreadBits(std::uint32_t(c.y)) << 1 | spreadBits(std::uint32_t(c.z)) << 2;
      keys[i] = std::uint64_t(code) << 32 | std::uint32_t(i);
    }
  });
  radixSortByCode(keys);  // the keys came in index order, so equal codes stay in it
  return keys;
}

}  // namespace isoatlas
