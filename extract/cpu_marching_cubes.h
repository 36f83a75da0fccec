// marchingCubesCpu: marching cubes (marching_cubes.h) on the CPU, row by row in parallel (TBB): three
// passes over the rows of grid points (count, exclusive sums, emit), no search, the rows kept as bits
// (bit_rows.h: which points are inside, which edges get a vertex), so the passes test 64 points at a
// time and visit only the cells the surface crosses; vertices in (point, axis) order across the whole
// grid, centre vertices after them, triangles in cell order.
#pragma once
#include "extract/marching_cubes.h"

namespace isoatlas::extract {

MarchingResult marchingCubesCpu(const Grid& grid, float iso, int blockSize = 8, const VisitBlock& visitBlock = {});

}  // namespace isoatlas::extract
