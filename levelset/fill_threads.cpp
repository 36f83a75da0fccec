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
  auto inside = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return inVolume(x, y, z) && in[mask.index(x, y, z)] != 0; };
  // A thread's voxel, whose 3 x 3 x 3 is `around`: background, almost all of its neighbours inside.
  auto isThread = [&](std::int64_t x, std::int64_t y, std::int64_t z, std::uint32_t around) {
    return inVolume(x, y, z) && !in[mask.index(x, y, z)] && 26 - std::popcount(around) <= kThreadNeighbours;
  };
  auto aroundOf = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return insideBits([&](int dx, int dy, int dz) { return inside(x + dx, y + dy, z + dz); });
  };
  std::deque<std::array<std::int64_t, 3>> queue;
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x)
        if (!in[mask.index(x, y, z)] && isThread(x, y, z, aroundOf(x, y, z))) queue.push_back({x, y, z});
  std::int64_t filled = 0;
  while (!queue.empty()) {
    const auto [x, y, z] = queue.front();
    queue.pop_front();
    if (inside(x, y, z)) continue;  // queued twice, taken in already
    const std::uint32_t around = aroundOf(x, y, z);  // read once: the thread test and the simple-point test
    if (!isThread(x, y, z, around) || !isSimplePoint(around)) continue;
    in[mask.index(x, y, z)] = 1;
    ++filled;
    // Its background neighbours may now be a thread's end: they are tested when taken from the queue.
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (inVolume(x + dx, y + dy, z + dz) && !inside(x + dx, y + dy, z + dz)) queue.push_back({x + dx, y + dy, z + dz});
  }
  return filled;
}

}  // namespace isoatlas::levelset
