// reconstructLevel: the surface at uniform level L, every tile refined alike by sampling its chart
// (the 4-8 refinement the adaptive mesh makes, here everywhere at once):
//   level 0       each tile's two base triangles (its corners);
//   level 2m      a 2^m x 2^m grid of the chart's texels, each square cut along its main diagonal
//                 (the p -> q direction) when its column plus row is even, else the other;
//   level 2m + 1  level 2m with each square's centre texel joined to its four corners.
// maxLevel(N) = 2 log2(N - 1) takes every texel of the chart (level 10 for N = 33).
// With detail charts (stampDetail) the levels go on to 2 log2(M - 1) for detail charts of M texels:
// there the tiles that have one refine further (the region refined locally) while the others stay at
// their finest, and the coarser side of each border between them is fanned to the finer samples;
// levels up to maxLevel(N) read the tiles' own charts only.
// Vertices on a tile's sides are shared with the tile across (one per base vertex and per sample
// of a base edge), so the mesh is closed and manifold where the base mesh is; positions and
// normals come from the atlas, where neighbouring charts hold the same border samples.
// Throws Error(BadInput) for a level outside 0 .. maxLevel or an atlas of another base mesh.
#pragma once
#include <array>
#include <cstdint>

#include "atlas/atlas.h"
#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

// The two triangles square (a, b) (column, row) of an even level's grid is cut into, as corners of
// the square counter-clockwise from (a, b): 0 (a, b), 1 (a + 1, b), 2 (a + 1, b + 1), 3 (a, b + 1).
// Along its main diagonal, 0 to 2, when a + b is even; else along the other.
constexpr std::array<std::array<int, 3>, 2> squareTriangles(std::uint32_t a, std::uint32_t b) {
  if ((a + b) % 2 == 0) return {{{0, 1, 2}, {0, 2, 3}}};
  return {{{0, 1, 3}, {1, 2, 3}}};
}

int maxLevel(std::uint32_t chartSize);
int maxLevel(const Atlas& atlas);  // with its detail charts
Mesh reconstructLevel(const multires::BaseMesh& base, const Atlas& atlas, int level);
// The faces of `tiles` alone (each tile once) of the mesh reconstructLevel makes, with the same
// positions and normals: open where a tile left out would join; its vertices numbered apart.
Mesh reconstructTiles(const multires::BaseMesh& base, const Atlas& atlas, int level, const std::vector<std::uint32_t>& tiles);

}  // namespace isoatlas::atlas
