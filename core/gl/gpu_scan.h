// GpuScan: in-place exclusive prefix sums of uint32 values in a GL buffer (Blelloch, 1024 values per
// work group, recursing on the groups' totals), with the programs of the context current when it is
// made (which must be current whenever it runs). The groups' totals live in buffers kept between
// scans (grown by doubling), so a scan allocates nothing once warm.
#pragma once
#include <array>
#include <cstdint>

#include "core/gl/context.h"
#include "core/gl/resources.h"

namespace isoatlas::gl {

class GpuScan {
public:
  GpuScan();
  // Scans the first `count` values; returns their total (a read back).
  std::uint32_t exclusive(Buffer& values, std::uint32_t count);
  // Scans as many values as the word counts[countIndex] says, at most `maxCount`, without reading
  // anything back: for chains of passes where an earlier one wrote the count. The total is left to
  // the caller (after values[count - 1] + the last value, or at values[count] when that was 0).
  void exclusive(Buffer& values, const Buffer& counts, std::uint32_t countIndex, std::uint32_t maxCount);

private:
  void scanLevel(Buffer& values, std::uint32_t count, std::size_t level, const Buffer* counts, std::uint32_t countIndex);
  Buffer& sumsOf(std::size_t level, std::uint32_t groups);

  const Program &scanBlocks_, &addOffsets_, &scanBlocksOnDevice_, &addOffsetsOnDevice_;
  std::array<Buffer, 4> sums_;  // per level of the recursion: 1024^4 values pass 32 bits
};

}  // namespace isoatlas::gl
