// marchingCubesGpu: the GPU twin of marchingCubes (marching_cubes.h), in GL 4.5 compute shaders
// (extract/shaders/): classify the cells of the visited blocks (triangle and centre counts, the grid
// edges used), compact by prefix sums, make each vertex once on the edge it lies on, then write the
// triangles. It gives the CPU's mesh: the same vertices (positions equal to float rounding) and the
// same triangles, numbered block by block (visited blocks in order, cells and points in each block
// in order) where the CPU numbers them across the whole grid.
// The field is the grid's dense values (uploaded), or, for a Grid whose paged.texture is set, phi in
// a GPU level set's page pool, read in place through its page table: no dense copy of phi on the host
// or the GPU. Its GPU memory, the field's besides, follows the visited blocks (about 24 bytes per
// visited cell), plus two small tables over the grid (4 bytes per page and per 8^3 block).
// Runs in the current GL context (gl::Context::current(), checked); a paged texture must belong to it.
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
