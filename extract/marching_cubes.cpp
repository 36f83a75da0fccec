#include "extract/marching_cubes.h"

#include "extract/cpu_marching_cubes.h"
#include "extract/gpu_marching_cubes.h"

namespace isoatlas::extract {

MarchingResult marchingCubes(levelset::Backend backend, const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock) {
  return backend == levelset::Backend::Gpu ? marchingCubesGpu(grid, iso, blockSize, visitBlock)
                                           : marchingCubesCpu(grid, iso, blockSize, visitBlock);
}

}  // namespace isoatlas::extract
