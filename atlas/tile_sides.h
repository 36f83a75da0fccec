// The four sides of a tile's chart, each a base edge shared with at most one other tile: side 0
// runs p -> s (texels (m, 0)), side 1 s -> q ((N-1, m)), side 2 q -> r ((N-1-m, N-1)), side 3 r -> p
// ((0, N-1-m)), for m = 0 .. N-1 from the side's first base vertex to its second.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct TileSide {
  std::uint32_t from, to;  // base vertices
};
inline std::array<TileSide, 4> tileSides(const multires::BaseMesh& base, std::uint32_t tile) {
  const auto c = base.tileCorners(tile);
  return {TileSide{c.p, c.s}, TileSide{c.s, c.q}, TileSide{c.q, c.r}, TileSide{c.r, c.p}};
}
// Texel (i, j) of step m along side `side` of a chart of `n` texels a side.
inline std::array<std::uint32_t, 2> sideTexel(int side, std::uint32_t m, std::uint32_t n) {
  switch (side) {
    case 0: return {m, 0};
    case 1: return {n - 1, m};
    case 2: return {n - 1 - m, n - 1};
    default: return {0, n - 1 - m};
  }
}

// The chart point at fraction t of side `side`, from its first base vertex to its second.
inline multires::Vec2 sidePoint(int side, double t) {
  switch (side) {
    case 0: return {t, 0};
    case 1: return {1, t};
    case 2: return {1 - t, 1};
    default: return {0, 1 - t};
  }
}

// Per tile and side, the tile and side across the same base edge (run the other way), found
// through the base triangles' neighbours; tile kNoTile on the mesh's boundary.
inline constexpr std::uint32_t kNoTile = ~0u;
struct SideAcross {
  std::uint32_t tile = kNoTile;
  int side = -1;
};
std::vector<std::array<SideAcross, 4>> sidesAcross(const multires::BaseMesh& base);

}  // namespace isoatlas::atlas
