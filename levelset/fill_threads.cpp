#include "levelset/fill_threads.h"

#include <array>
#include <bit>
#include <deque>

#include "core/error.h"
#include "levelset/simple_point.h"

namespace isoatlas::levelset {

std::int64_t fillThreads(Volume& mask) {
  require(mask.type == ScalarType::UInt8, "fillThreads needs a uint8 mask");
  const auto dims = mask.dims;
  auto* in = reinterpret_cast<std::uint8_t*>(mask.data.data());
  auto inVolume = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2];
  };
  auto insideAround = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    std::uint32_t bits = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (inVolume(x + dx, y + dy, z + dz) && in[mask.index(x + dx, y + dy, z + dz)])
            bits |= 1u << ((dz + 1) * 9 + (dy + 1) * 3 + dx + 1);
    return bits;
  };
  // A thread's voxel: background, almost all of its 3 x 3 x 3 inside.
  auto isThread = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    if (!inVolume(x, y, z) || in[mask.index(x, y, z)]) return false;
    const std::uint32_t around = insideAround(x, y, z) & ~(1u << 13);
    return 26 - std::popcount(around) <= kThreadNeighbours;
  };
  std::deque<std::array<std::int64_t, 3>> queue;
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x)
        if (isThread(x, y, z)) queue.push_back({x, y, z});
  std::int64_t filled = 0;
  while (!queue.empty()) {
    const auto [x, y, z] = queue.front();
    queue.pop_front();
    if (!isThread(x, y, z) || !isSimplePoint(insideAround(x, y, z))) continue;
    in[mask.index(x, y, z)] = 1;
    ++filled;
    // Its background neighbours may now be a thread's end.
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (isThread(x + dx, y + dy, z + dz)) queue.push_back({x + dx, y + dy, z + dz});
  }
  return filled;
}

}  // namespace isoatlas::levelset
