// marchingCubesGpu: the GPU twin of marchingCubes (marching_cubes.h), in GL 4.5 compute shaders
// (extract/shaders/): classify the cells of the visited blocks (triangle and centre counts, the grid
// edges used), compact by prefix sums, make each vertex once on the edge it lies on, then write the
// triangles. It gives the CPU's mesh: the same vertices in the same order (positions equal to float
// rounding), the same triangles in the same (cell) order.
// Creates its own headless GL context (a GPU through EGL, else Mesa's llvmpipe).
#pragma once
#include "extract/marching_cubes.h"

namespace isoatlas::extract {

MarchingResult marchingCubesGpu(const Grid& grid, float iso, int blockSize = 8,
                                const std::function<bool(std::int64_t, std::int64_t, std::int64_t)>& visitBlock = {});

// The case table as the shaders read it: per case (offset into polygons, polygon count); a polygon
// is apex (or -1), corner count n, then n cell edges. Defined in marching_cubes.cpp.
struct PackedCaseTable {
  std::vector<std::int32_t> index;     // 2 per case
  std::vector<std::int32_t> polygons;
};
const PackedCaseTable& packedCaseTable();

}  // namespace isoatlas::extract
