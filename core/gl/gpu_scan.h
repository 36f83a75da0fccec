// GpuScan: in-place exclusive prefix sums of uint32 values in a GL buffer (Blelloch, 1024 values per
// work group, recursing on the groups' totals), with the programs of the context current when it is
// made (which must be current whenever it runs).
#pragma once
#include <cstdint>

#include "core/gl/context.h"
#include "core/gl/resources.h"

namespace isoatlas::gl {

class GpuScan {
public:
  GpuScan();
  // Scans the first `count` values; returns their total.
  std::uint32_t exclusive(Buffer& values, std::uint32_t count);

private:
  const Program &scanBlocks_, &addOffsets_;
};

}  // namespace isoatlas::gl
