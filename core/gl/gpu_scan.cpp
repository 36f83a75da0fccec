#include "core/gl/gpu_scan.h"

#include <algorithm>

#include "kGlShaders.h"

namespace isoatlas::gl {

GpuScan::GpuScan()
    : scanBlocks_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp", {{"SCAN_BLOCKS", "1"}})),
      addOffsets_(Context::current().compute(kGlShaders, "core/gl/shaders/scan.comp")) {}

std::uint32_t GpuScan::exclusive(Buffer& values, std::uint32_t count) {
  if (count == 0) return 0;
  const std::uint32_t groups = (count + 1023) / 1024;
  Buffer sums(std::size_t(groups) * 4 + 4);
  const auto [gx, gy] = dispatchGrid(groups);
  values.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  sums.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
  scanBlocks_.use();
  glUniform1ui(scanBlocks_.uniform("count"), count);
  scanBlocks_.dispatch(gx, gy, 1, GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  std::uint32_t total = 0;
  if (groups == 1) {
    sums.download(&total, 4);
    return total;
  }
  total = exclusive(sums, groups);
  values.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  sums.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
  addOffsets_.use();
  glUniform1ui(addOffsets_.uniform("count"), count);
  addOffsets_.dispatch(gx, gy, 1, GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  return total;
}

}  // namespace isoatlas::gl
