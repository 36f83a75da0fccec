// Checks of an atlas the atlas tests share.
#pragma once
#include <gtest/gtest.h>

#include <cstring>
#include <map>

#include "atlas/atlas.h"
#include "atlas/tile_sides.h"
#include "multires/base_mesh.h"

namespace isoatlas::test {

// Every tile side's texels, as raw bits, equal those of every other chart on the same base edge
// (read in the same direction), in the tiles' charts and, where both tiles have one, in their
// detail charts; every corner texel is its base vertex unless a stamp may have moved it. Returns the
// shared sides counted (each shared edge twice, once from each tile).
inline std::size_t expectIdenticalBorders(const multires::BaseMesh& base, const atlas::Atlas& atlas, bool stamped = false) {
  std::map<std::uint32_t, const atlas::DetailChart*> detail;
  for (const atlas::DetailChart& d : atlas.details) detail[d.tile] = &d;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::uint32_t, int>>> edges;
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) {
    const auto sides = atlas::tileSides(base, c);
    for (int s = 0; s < 4; ++s) edges[{sides[s].from, sides[s].to}].push_back({c, s});
  }
  std::size_t shared = 0;
  for (const auto& [edge, list] : edges) {
    const auto reverse = edges.find({edge.second, edge.first});
    const std::uint32_t n = atlas.layout.chartSize;
    const Vec3 from = base.positions[edge.first];
    const auto corner = atlas::sideTexel(list[0].second, 0, n);
    const std::array<float, 3> expected{float(from.x), float(from.y), float(from.z)};
    if (!stamped) {
      EXPECT_EQ(atlas.positions[atlas.layout.texel(list[0].first, corner[0], corner[1])], expected);
    }
    if (reverse == edges.end()) continue;
    for (const auto& [c, s] : list)
      for (const auto& [d, t] : reverse->second) {
        ++shared;
        for (std::uint32_t m = 0; m < n; ++m) {
          const auto a = atlas::sideTexel(s, m, n), z = atlas::sideTexel(t, n - 1 - m, n);
          const std::size_t at = atlas.layout.texel(c, a[0], a[1]), other = atlas.layout.texel(d, z[0], z[1]);
          EXPECT_EQ(std::memcmp(&atlas.positions[at], &atlas.positions[other], sizeof(atlas.positions[at])), 0)
              << "charts " << c << " and " << d << " differ at step " << m;
          EXPECT_EQ(atlas.normals[at], atlas.normals[other]);
          if (::testing::Test::HasFailure()) return shared;
        }
        if (!detail.count(c) || !detail.count(d)) continue;
        const atlas::DetailChart &dc = *detail[c], &dd = *detail[d];
        for (std::uint32_t m = 0; m < dc.size; ++m) {
          const auto a = atlas::sideTexel(s, m, dc.size), z = atlas::sideTexel(t, dc.size - 1 - m, dc.size);
          const std::size_t at = std::size_t(a[1]) * dc.size + a[0], other = std::size_t(z[1]) * dd.size + z[0];
          EXPECT_EQ(std::memcmp(&dc.positions[at], &dd.positions[other], sizeof(dc.positions[at])), 0)
              << "detail charts of tiles " << c << " and " << d << " differ at step " << m;
          EXPECT_EQ(dc.normals[at], dd.normals[other]);
          if (::testing::Test::HasFailure()) return shared;
        }
      }
  }
  return shared;
}

}  // namespace isoatlas::test
