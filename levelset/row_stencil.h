// The level-set update of speed.h, page rows at a time, with each face normal of the curvature
// computed once for the two voxels that share the face: along a row (x faces) and between one row
// and the next (y faces); z faces lie between pages and stay two a voxel (computing them once, up
// columns of pages, gained nothing measurable). Every value is computed from the same operands in the same order as evaluateVoxelAt (additions only swapped, which IEEE
// arithmetic leaves exact), so the results are evaluateVoxelAt's bit for bit (tested), and the GLSL
// twin stays line for line with speed.h.
//
// The apron is a page's values with a one-voxel border, [dz + 1][y + 1][x + 1], side P + 2 (P at most
// kMaxPageSize). Compiled for AVX2 and the baseline (core/cpu_dispatch.h), without floating-point
// contraction, so both give the same bits.
#pragma once
#include <cstddef>
#include <cstdint>

#include "levelset/page_manager.h"
#include "levelset/speed.h"

namespace isoatlas::levelset {


// Inputs: apron, side (P + 2), rows y0 <= y < y1 within [-1, P - 1], xEnd <= P.
// Output: faces[(y - y0) * kMaxPageSize + x] for x < xEnd, the normal on the face between voxel
//   (x, y) and (x, y + 1).
void rowFaceNormals(const float* apron, int side, int y0, int y1, int xEnd, float* faces);

// Inputs: apron, side, rows y0 <= y < y1 within [0, P - 1], xEnd <= P; intensity: I at voxel (x, y)
//   at intensity[(y - y0) * intensityStride + x]; params; faces: rowFaceNormals of rows y0 - 1 to y1 - 1.
// Outputs: speed and rate at [(y - y0) * stride + x] for x < xEnd, as evaluateVoxelAt gives them;
//   moving[y - y0]: bit x set where that rate is not zero (the voxels that move).
void evaluateRows(const float* apron, int side, int y0, int y1, int xEnd, const float* intensity,
                  std::size_t intensityStride, SpeedParams params, const float* faces, std::size_t stride,
                  float* speed, float* rate, std::uint32_t* moving);

}  // namespace isoatlas::levelset
