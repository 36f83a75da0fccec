#include "atlas/reconstruct.h"

#include <bit>
#include <unordered_map>

#include "atlas/tile_sides.h"
#include "core/error.h"

namespace isoatlas::atlas {
namespace {

// One mesh vertex per base vertex, per sample of a base edge, and per interior texel of a chart
// (asked for chart by chart).
class VertexNumbering {
public:
  VertexNumbering(const multires::BaseMesh& base, const Atlas& atlas, Mesh& mesh)
      : base_(base), atlas_(atlas), n_(atlas.layout.chartSize), mesh_(mesh), baseVertex_(base.vertexCount(), kNone) {}

  std::uint32_t of(std::uint32_t chart, std::uint32_t i, std::uint32_t j) {
    const std::uint32_t last = n_ - 1;
    if (i > 0 && i < last && j > 0 && j < last) {
      if (chart != chart_) chart_ = chart, interior_.assign(std::size_t(n_) * n_, kNone);
      std::uint32_t& id = interior_[std::size_t(j) * n_ + i];
      if (id == kNone) id = add(chart, i, j);
      return id;
    }
    // On a side: which one, and the step along it from its first base vertex.
    const int side = j == 0 ? 0 : i == last ? 1 : j == last ? 2 : 3;
    const std::uint32_t m = side == 0 ? i : side == 1 ? j : side == 2 ? last - i : last - j;
    const TileSide s = tileSides(base_, chart)[side];
    if (m == 0 || m == last) {
      std::uint32_t& id = baseVertex_[m == 0 ? s.from : s.to];
      if (id == kNone) id = add(chart, i, j);
      return id;
    }
    const std::uint64_t lo = std::min(s.from, s.to), hi = std::max(s.from, s.to);
    const std::uint64_t along = s.from < s.to ? m : last - m;
    const auto [it, added] = edgeSample_.try_emplace(((lo * base_.vertexCount() + hi) << 8) | along, 0);
    if (added) it->second = add(chart, i, j);
    return it->second;
  }

private:
  static constexpr std::uint32_t kNone = ~0u;
  std::uint32_t add(std::uint32_t chart, std::uint32_t i, std::uint32_t j) {
    mesh_.positions.push_back(atlas_.position(chart, i, j));
    mesh_.normals.push_back(atlas_.normal(chart, i, j));
    return std::uint32_t(mesh_.positions.size() - 1);
  }
  const multires::BaseMesh& base_;
  const Atlas& atlas_;
  std::uint32_t n_;
  Mesh& mesh_;
  std::vector<std::uint32_t> baseVertex_;
  std::uint32_t chart_ = kNone;          // whose interior texels interior_ numbers
  std::vector<std::uint32_t> interior_;  // per texel of chart_
  std::unordered_map<std::uint64_t, std::uint32_t> edgeSample_;  // (edge, texel along it) -> vertex
};

}  // namespace

int maxLevel(std::uint32_t chartSize) {
  require(multires::isChartSize(chartSize), "atlas: chart size " + std::to_string(chartSize) + " is not 2^k + 1");
  return 2 * std::countr_zero(chartSize - 1);
}

Mesh reconstructLevel(const multires::BaseMesh& base, const Atlas& atlas, int level) {
  const std::uint32_t n = atlas.layout.chartSize;
  require(level >= 0 && level <= maxLevel(n), "level " + std::to_string(level) + " is outside 0.." +
                                                  std::to_string(maxLevel(n)) + " for charts of " + std::to_string(n) + " texels");
  require(atlas.layout.charts == base.tiles.size(), "atlas: it holds " + std::to_string(atlas.layout.charts) +
                                                        " charts, the base mesh has " + std::to_string(base.tiles.size()) + " tiles");
  Mesh mesh;
  VertexNumbering vertex(base, atlas, mesh);
  const std::uint32_t squares = 1u << (level / 2), step = (n - 1) / squares;
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c)
    for (std::uint32_t b = 0; b < squares; ++b)
      for (std::uint32_t a = 0; a < squares; ++a) {
        const std::uint32_t i = a * step, j = b * step;
        // Corners counter-clockwise in (u, v), as the tile on the surface.
        const std::uint32_t v00 = vertex.of(c, i, j), v10 = vertex.of(c, i + step, j);
        const std::uint32_t v11 = vertex.of(c, i + step, j + step), v01 = vertex.of(c, i, j + step);
        if (level % 2 == 1) {
          const std::uint32_t centre = vertex.of(c, i + step / 2, j + step / 2);
          mesh.addFace({v00, v10, centre}), mesh.addFace({v10, v11, centre});
          mesh.addFace({v11, v01, centre}), mesh.addFace({v01, v00, centre});
        } else if ((a + b) % 2 == 0) {
          mesh.addFace({v00, v10, v11}), mesh.addFace({v00, v11, v01});
        } else {
          mesh.addFace({v00, v10, v01}), mesh.addFace({v10, v11, v01});
        }
      }
  return mesh;
}

}  // namespace isoatlas::atlas
