// PagedPhiCpu: a level set's phi read on the host straight from its pages, the CPU twin of
// PagedPhiGpu (paged_phi_gpu.h): each voxel through the page table into the pool, inactive pages
// reading the static inside/outside slots. No dense copy.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "levelset/page_manager.h"

namespace isoatlas::levelset {

struct PagedPhiCpu {
  const PageManager* pages = nullptr;
  const float* pool = nullptr;  // the pool on the host (LevelSet::phiPoolOnHost)

  float at(std::int64_t x, std::int64_t y, std::int64_t z) const { return pool[pages->poolTexel(x, y, z)]; }
  // Row (y, z), voxels 0 .. width - 1, copied into `scratch` (a page's row lies contiguous in the pool).
  const float* row(std::int64_t y, std::int64_t z, std::int64_t width, std::vector<float>& scratch) const {
    const int P = pages->pageSize();
    scratch.resize(std::size_t(width));
    for (std::int64_t x0 = 0; x0 < width; x0 += P)
      std::copy_n(pool + pages->poolTexel(x0, y, z), std::min<std::int64_t>(P, width - x0), scratch.data() + x0);
    return scratch.data();
  }
};

}  // namespace isoatlas::levelset
