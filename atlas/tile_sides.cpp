#include "atlas/tile_sides.h"

namespace isoatlas::atlas {

std::vector<std::array<SideAcross, 4>> sidesAcross(const multires::BaseMesh& base) {
  const auto neighbours = base.triangleNeighbours();
  std::vector<std::uint32_t> tileOf(base.triangleCount(), kNoTile);
  for (std::uint32_t t = 0; t < base.tiles.size(); ++t) tileOf[base.tiles[t][0]] = tileOf[base.tiles[t][1]] = t;
  std::vector<std::array<SideAcross, 4>> across(base.tiles.size());
  for (std::uint32_t t = 0; t < base.tiles.size(); ++t) {
    const auto sides = tileSides(base, t);
    for (int k = 0; k < 4; ++k)
      for (const std::uint32_t triangle : base.tiles[t])
        for (int e = 0; e < 3; ++e) {
          const auto& c = base.triangles[triangle];
          if (c[e] != sides[k].from || c[(e + 1) % 3] != sides[k].to) continue;
          const std::uint32_t other = neighbours[triangle][e];
          if (other == multires::BaseMesh::kNoTriangle || tileOf[other] == kNoTile) continue;
          const auto otherSides = tileSides(base, tileOf[other]);
          for (int j = 0; j < 4; ++j)
            if (otherSides[j].from == sides[k].to && otherSides[j].to == sides[k].from) across[t][k] = {tileOf[other], j};
        }
  }
  return across;
}

}  // namespace isoatlas::atlas
