#include "core/gl/gpu_scan.h"

#include <algorithm>

#include "kGlShaders.h"

namespace isoatlas::gl {
namespace {
constexpr GLbitfield kBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;
}

GpuScan::GpuScan()
    : scanBlocks_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp", {{"SCAN_BLOCKS", "1"}})),
      addOffsets_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp")),
      scanBlocksOnDevice_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp", {{"SCAN_BLOCKS", "1"}, {"DEVICE_COUNT", "1"}})),
      addOffsetsOnDevice_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp", {{"DEVICE_COUNT", "1"}})) {}

std::uint32_t GpuScan::exclusive(Buffer& values, std::uint32_t count) {
  if (count == 0) return 0;
  scanLevel(values, count, 0, nullptr, 0);
  std::uint32_t total = 0;
  const std::uint32_t groups = (count + 1023) / 1024;
  // The top level's one group total is the sum of everything.
  std::size_t top = 0;
  for (std::uint32_t n = groups; n > 1; n = (n + 1023) / 1024) ++top;
  sums_[top].download(&total, 4);
  return total;
}

void GpuScan::exclusive(Buffer& values, const Buffer& counts, std::uint32_t countIndex, std::uint32_t maxCount) {
  if (maxCount > 0) scanLevel(values, maxCount, 0, &counts, countIndex);
}

Buffer& GpuScan::sumsOf(std::size_t level, std::uint32_t groups) {
  const std::size_t bytes = std::size_t(groups) * 4 + 4;
  if (sums_[level].bytes() < bytes) sums_[level] = Buffer(std::max(bytes, 2 * sums_[level].bytes()));
  return sums_[level];
}

// `count`: the values at this level, or with `counts` the most there can be (the shaders read the
// level's count from counts[countIndex], divided up by 1024 per level).
void GpuScan::scanLevel(Buffer& values, std::uint32_t count, std::size_t level, const Buffer* counts, std::uint32_t countIndex) {
  const std::uint32_t groups = (count + 1023) / 1024;
  Buffer& sums = sumsOf(level, groups);
  const auto [gx, gy] = dispatchGrid(groups);
  const auto bind = [&](const Program& program) {
    values.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    sums.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    program.use();
    if (counts) {
      counts->bindBase(GL_SHADER_STORAGE_BUFFER, 2);
      glUniform1ui(program.uniform("countIndex"), countIndex);
      glUniform1ui(program.uniform("levelShift"), GLuint(10 * level));
    } else {
      glUniform1ui(program.uniform("count"), count);
    }
  };
  const Program& blocks = counts ? scanBlocksOnDevice_ : scanBlocks_;
  bind(blocks);
  blocks.dispatch(gx, gy, 1, kBarrier);
  if (groups == 1) return;
  scanLevel(sums, groups, level + 1, counts, countIndex);
  const Program& add = counts ? addOffsetsOnDevice_ : addOffsets_;
  bind(add);
  add.dispatch(gx, gy, 1, kBarrier);
}

}  // namespace isoatlas::gl
