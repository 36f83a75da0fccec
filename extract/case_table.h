// The marching-cubes case table both paths read: for each of the 256 inside/outside patterns of a
// cell, its polygons as cycles of cell edges (face-consistent: marching_cubes.h says why), each
// fanned from an apex corner or a centre vertex. packedCaseTable() is the same, flat, as the GPU
// path's shaders read it.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace isoatlas::extract {

// Corner k of a cell sits at (k & 1, (k >> 1) & 1, (k >> 2) & 1). Edge e joins kEdgeCorner[e][0] to
// kEdgeCorner[e][1] along axis kEdgeAxis[e], from the lower corner.
inline constexpr int kEdgeCorner[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
inline constexpr int kEdgeAxis[12] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

struct Polygon {
  std::vector<std::int8_t> edges;  // the cycle of cell edges, outward orientation
  int apex;                        // fan from this corner, or -1: fan from a centre vertex of its own
};

struct CaseTable {
  std::array<std::vector<Polygon>, 256> polygons;
  CaseTable();
};
const CaseTable& caseTable();

// The case table as the shaders read it: per case (offset into polygons, polygon count); a polygon
// is apex (or -1), corner count n, then n cell edges.
struct PackedCaseTable {
  std::vector<std::int32_t> index;     // 2 per case
  std::vector<std::int32_t> polygons;
};
const PackedCaseTable& packedCaseTable();

}  // namespace isoatlas::extract
