// marchingCubes: the isosurface {f = iso} of a scalar field on a grid, as a closed, 2-manifold,
// consistently oriented triangle mesh, on the CPU (cpu_marching_cubes.h, TBB) or the GPU
// (gpu_marching_cubes.h, GL 4.5 compute), which give the same mesh.
//   Each cell's surface is traced from its faces: on every face the crossing points are paired into
//   segments by a rule that depends on that face alone (on an ambiguous face the two inside corners
//   are kept apart), so the two cells sharing a face always agree; the segments chain into polygons,
//   which are fanned into triangles. Every vertex lies on a grid edge and is shared by the cells
//   around that edge. Hence: every mesh edge has exactly two triangles, every vertex one fan.
//   Inside is f > iso; a corner equal to iso counts as outside, and crossing points are kept a small
//   distance off the corners, so no triangle is degenerate. Outside the grid counts as outside (the
//   field is padded), so a surface touching the border is closed there.
//   Triangles are oriented counter-clockwise seen from outside (normals point out of {f > iso}).
// Positions are in voxel index coordinates (the caller maps them to the world).
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"
#include "levelset/backend.h"
#include "levelset/paged_phi_cpu.h"

namespace isoatlas::extract {

// A scalar field on dims grid points, x fastest: dense `values`, or a level set's pages (no dense
// copy anywhere): on the host for the CPU path, its pool texture (r32f, in the current GL context)
// for the GPU path.
struct Grid {
  std::array<std::int64_t, 3> dims;
  const float* values = nullptr;
  levelset::PagedPhiCpu paged = {};  // paged.pages also gives the GPU path its page table
  unsigned pagedTexture = 0;
  std::size_t voxels() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
  float at(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return values ? values[std::size_t((z * dims[1] + y) * dims[0] + x)] : paged.at(x, y, z);
  }
  // Row (y, z): dims[0] values, copied into `scratch` when paged.
  const float* row(std::int64_t y, std::int64_t z, std::vector<float>& scratch) const {
    return values ? values + std::size_t((z * dims[1] + y) * dims[0]) : paged.row(y, z, dims[0], scratch);
  }
};

struct MarchingResult {
  Mesh mesh;
  std::int64_t cellsVisited = 0;
  std::uint64_t gpuBytes = 0;  // GPU memory the extraction allocated (the GPU path; a paged field's pool not counted)
};

// Blocks of blockSize cells along an axis of `points` grid points: block b holds cells
// b * blockSize - 1 .. first + blockSize - 1, the last block clipped at cell points - 1.
struct BlockCells {
  std::int64_t first, last;
};
inline std::int64_t blockCount(std::int64_t points, int blockSize) { return (points + blockSize) / blockSize; }
inline BlockCells blockCells(std::int64_t b, int blockSize, std::int64_t points) {
  return {b * blockSize - 1, std::min(b * blockSize + blockSize - 2, points - 1)};
}

using VisitBlock = std::function<bool(std::int64_t bx, std::int64_t by, std::int64_t bz)>;

// Cells are the cubes between grid points, from (-1,-1,-1) to dims-1 (the padding included).
// `visitBlock` says which blocks of blockSize^3 cells to visit (e.g. those touching an active page of
// a level set); others are skipped. Blocks are indexed from cell -1. With none given, the blocks that
// straddle iso are visited (straddling_blocks.h), the only ones with surface: the CPU path finds them
// from the inside bits it keeps anyway, the GPU path from a dense grid's values on the host (on the
// GPU a paged grid needs visitBlock).
// On the GPU backend it runs in the current GL context (gl::Context::current(), checked).
MarchingResult marchingCubes(levelset::Backend backend, const Grid& grid, float iso, int blockSize = 8,
                             const VisitBlock& visitBlock = {});

}  // namespace isoatlas::extract
