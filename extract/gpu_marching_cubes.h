// marchingCubesGpu: marching cubes (marching_cubes.h) on the GPU, the twin of marchingCubesCpu, in GL 4.5 compute shaders
// (extract/shaders/): classify the cells of the visited blocks (triangle and centre counts, the grid
// edges used), compact by prefix sums, make each vertex once on the edge it lies on, then write the
// triangles. It gives the CPU's mesh: the same vertices (positions equal to float rounding) and the
// same triangles, numbered block by block (visited blocks in order, cells and points in each block
// in order) where the CPU numbers them across the whole grid.
// The field is the grid's dense values (uploaded), or, for a Grid whose pagedTexture is set, phi in
// a GPU level set's page pool, read in place through its page table: no dense copy of phi on the host
// or the GPU. Its GPU memory, the field's besides, follows the visited blocks (about 24 bytes per
// visited cell), plus two small tables over the grid (4 bytes per page and per 8^3 block).
// With no visitBlock, a dense grid's straddling blocks are chosen on the host (straddling_blocks.h);
// a paged grid needs visitBlock.
// Runs in the current GL context (gl::Context::current(), checked); a paged texture must belong to it.
#pragma once
#include "extract/marching_cubes.h"

namespace isoatlas::extract {

MarchingResult marchingCubesGpu(const Grid& grid, float iso, int blockSize = 8, const VisitBlock& visitBlock = {});

}  // namespace isoatlas::extract
