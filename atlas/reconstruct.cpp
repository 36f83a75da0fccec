#include "atlas/reconstruct.h"

#include <bit>
#include <unordered_map>

#include "atlas/tile_sides.h"
#include "core/error.h"

namespace isoatlas::atlas {
namespace {

// Where texel (I, J) of a tile, in units of the finest chart (`fine` texels a side), is read from:
// the tile's detail chart when it has one and the level uses it, else its own chart.
struct Source {
  const Atlas& atlas;
  std::uint32_t fine, ratio;           // fine = (chartSize - 1) * ratio + 1
  std::vector<const DetailChart*> detail;  // per tile, or null; null for all when the level uses none

  Vec3 position(std::uint32_t c, std::uint32_t I, std::uint32_t J) const {
    return detail[c] ? detail[c]->position(I, J) : atlas.position(c, I / ratio, J / ratio);
  }
  Vec3 normal(std::uint32_t c, std::uint32_t I, std::uint32_t J) const {
    return detail[c] ? detail[c]->normal(I, J) : atlas.normal(c, I / ratio, J / ratio);
  }
};

// One mesh vertex per base vertex, per sample of a base edge, and per interior texel of a chart
// (asked for chart by chart), texels counted in the finest chart's units.
class VertexNumbering {
public:
  VertexNumbering(const multires::BaseMesh& base, const Source& source, Mesh& mesh)
      : base_(base), source_(source), mesh_(mesh), baseVertex_(base.vertexCount(), kNone) {}

  std::uint32_t of(std::uint32_t chart, std::uint32_t i, std::uint32_t j) {
    const std::uint32_t last = source_.fine - 1;
    if (i > 0 && i < last && j > 0 && j < last) {
      if (chart != chart_) chart_ = chart, interior_.assign(std::size_t(source_.fine) * source_.fine, kNone);
      std::uint32_t& id = interior_[std::size_t(j) * source_.fine + i];
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
    mesh_.positions.push_back(source_.position(chart, i, j));
    mesh_.normals.push_back(source_.normal(chart, i, j));
    return std::uint32_t(mesh_.positions.size() - 1);
  }
  const multires::BaseMesh& base_;
  const Source& source_;
  Mesh& mesh_;
  std::vector<std::uint32_t> baseVertex_;
  std::uint32_t chart_ = kNone;                                 // whose interior texels interior_ numbers
  std::vector<std::uint32_t> interior_;                         // per texel of chart_: its vertex
  std::unordered_map<std::uint64_t, std::uint32_t> edgeSample_;  // (edge, texel along it) -> vertex
};

}  // namespace

int maxLevel(std::uint32_t chartSize) {
  require(multires::isChartSize(chartSize), "atlas: chart size " + std::to_string(chartSize) + " is not 2^k + 1");
  return 2 * std::countr_zero(chartSize - 1);
}

int maxLevel(const Atlas& atlas) {
  return maxLevel(atlas.details.empty() ? atlas.layout.chartSize : atlas.details.front().size);
}

Mesh reconstructLevel(const multires::BaseMesh& base, const Atlas& atlas, int level) {
  std::vector<std::uint32_t> all(atlas.layout.charts);
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) all[c] = c;
  return reconstructTiles(base, atlas, level, all);
}

Mesh reconstructTiles(const multires::BaseMesh& base, const Atlas& atlas, int level, const std::vector<std::uint32_t>& tiles) {
  const std::uint32_t n = atlas.layout.chartSize;
  const int coarseTop = maxLevel(n), top = maxLevel(atlas);
  require(level >= 0 && level <= top, "level " + std::to_string(level) + " is outside 0.." + std::to_string(top) +
                                          " for charts of " + std::to_string(n) + " texels" +
                                          (atlas.details.empty() ? "" : " with detail charts"));
  require(atlas.layout.charts == base.tiles.size(), "atlas: it holds " + std::to_string(atlas.layout.charts) +
                                                        " charts, the base mesh has " + std::to_string(base.tiles.size()) + " tiles");
  const std::uint32_t fine = atlas.details.empty() ? n : atlas.details.front().size;
  Source source{atlas, fine, (fine - 1) / (n - 1), std::vector<const DetailChart*>(atlas.layout.charts, nullptr)};
  // Above the charts' own levels, the tiles with detail charts refine further and the rest stay at
  // their finest; the sides they share are stitched by fans in the coarser tile.
  const bool local = level > coarseTop;
  if (local)
    for (const DetailChart& d : atlas.details) source.detail[d.tile] = &d;
  auto stepOf = [&](std::uint32_t c) {
    const int l = local && !source.detail[c] ? coarseTop : level;
    return (fine - 1) >> (l / 2);
  };
  const auto across = local ? sidesAcross(base) : std::vector<std::array<SideAcross, 4>>{};

  Mesh mesh;
  VertexNumbering vertex(base, source, mesh);
  struct Corner {
    std::uint32_t i, j;
  };
  // Triangle (p, q, r) of chart c, counter-clockwise; an edge along a side whose tile across is
  // finer gets that tile's samples, fanned from the opposite corner.
  auto triangle = [&](std::uint32_t c, Corner p, Corner q, Corner r) {
    const std::uint32_t last = fine - 1, step = stepOf(c);
    const Corner corners[3] = {p, q, r};
    for (int e = 0; e < 3 && local; ++e) {
      const Corner a = corners[e], b = corners[(e + 1) % 3], o = corners[(e + 2) % 3];
      const int side = a.j == 0 && b.j == 0 ? 0 : a.i == last && b.i == last ? 1 : a.j == last && b.j == last ? 2
                       : a.i == 0 && b.i == 0 ? 3 : -1;
      if (side < 0 || across[c][side].tile == kNoTile) continue;
      const std::uint32_t finer = stepOf(across[c][side].tile);
      if (finer >= step) continue;
      const std::int64_t di = (std::int64_t(b.i) - a.i) / std::int64_t(step / finer), dj = (std::int64_t(b.j) - a.j) / std::int64_t(step / finer);
      const std::uint32_t apex = vertex.of(c, o.i, o.j);
      std::uint32_t from = vertex.of(c, a.i, a.j);
      for (std::uint32_t k = 1; k <= step / finer; ++k) {
        const std::uint32_t to = vertex.of(c, std::uint32_t(a.i + di * k), std::uint32_t(a.j + dj * k));
        mesh.addFace({from, to, apex});
        from = to;
      }
      return;  // a triangle of an even level has at most one edge on a side
    }
    mesh.addFace({vertex.of(c, p.i, p.j), vertex.of(c, q.i, q.j), vertex.of(c, r.i, r.j)});
  };
  // Tiles with detail charts first: the samples they put on a shared side are already numbered (and
  // read from the detail chart) when the coarser tile across fans to them.
  std::vector<std::uint32_t> order;
  std::vector<bool> listed(atlas.layout.charts, false);
  for (const std::uint32_t c : tiles) {
    require(c < atlas.layout.charts, "atlas: no tile " + std::to_string(c));
    listed[c] = true;
    if (source.detail[c]) order.push_back(c);
  }
  for (const std::uint32_t c : tiles)
    if (!source.detail[c]) order.push_back(c);
  // A detail tile left out still gives its samples to the sides it shares with listed tiles.
  for (const std::uint32_t c : order)
    for (int side = 0; side < 4 && local && !source.detail[c]; ++side) {
      const SideAcross d = across[c][side];
      if (d.tile == kNoTile || listed[d.tile] || !source.detail[d.tile]) continue;
      for (std::uint32_t m = 0; m < fine; m += stepOf(d.tile)) {
        const auto [i, j] = sideTexel(d.side, m, fine);
        vertex.of(d.tile, i, j);
      }
    }
  for (const std::uint32_t c : order) {
    const std::uint32_t step = stepOf(c), squares = (fine - 1) / step;
    const int l = local && !source.detail[c] ? coarseTop : level;
    for (std::uint32_t b = 0; b < squares; ++b)
      for (std::uint32_t a = 0; a < squares; ++a) {
        const std::uint32_t i = a * step, j = b * step;
        // Corners counter-clockwise in (u, v), as the tile on the surface.
        const Corner v00{i, j}, v10{i + step, j}, v11{i + step, j + step}, v01{i, j + step};
        if (l % 2 == 1) {
          const Corner centre{i + step / 2, j + step / 2};
          triangle(c, v00, v10, centre), triangle(c, v10, v11, centre);
          triangle(c, v11, v01, centre), triangle(c, v01, v00, centre);
        } else {
          const Corner square[4] = {v00, v10, v11, v01};
          for (const auto& t : squareTriangles(a, b)) triangle(c, square[t[0]], square[t[1]], square[t[2]]);
        }
      }
  }
  return mesh;
}

}  // namespace isoatlas::atlas
