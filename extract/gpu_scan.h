// GpuScan: in-place exclusive prefix sums of uint32 values in a GL buffer (Blelloch, 1024 values per
// work group, recursing on the groups' totals). Its programs belong to the GL context current when
// it is made; use it only while that context lives.
#pragma once
#include <cstdint>

#include "core/gl/program.h"
#include "core/gl/resources.h"

namespace isoatlas::extract {

class GpuScan {
public:
  GpuScan();
  // Scans the first `count` values; returns their total.
  std::uint32_t exclusive(gl::Buffer& values, std::uint32_t count);

private:
  gl::Program scanBlocks_, addOffsets_;
};

}  // namespace isoatlas::extract
