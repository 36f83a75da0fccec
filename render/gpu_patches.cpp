#include "render/gpu_patches.h"

#include <algorithm>
#include <bit>
#include <unordered_map>
#include <unordered_set>

namespace isoatlas::render {
namespace {

using multires::AdaptiveMesh;
using multires::Patch;

// The line a patch side lies on: a chart's interior row (kind 0, coordinate v) or column (kind 1,
// coordinate u), or a tile side (kind 2 + side, coordinate 0), named from the lower of its two tiles
// so that both charts name it alike. Positions run along it: u, v, or the tile side's step.
struct Line {
  std::uint32_t chart, kind, coordinate;
  std::uint64_t key() const { return std::uint64_t(chart) << 24 | kind << 16 | coordinate; }
};
struct Placed {
  Line line;
  std::uint32_t from, to;
  atlas::SideAcross across;  // on a tile side: the tile across (kNoTile: none, or not a tile side)
};

Placed place(const Patch& p, int side, std::uint32_t n, const std::vector<std::array<atlas::SideAcross, 4>>& across) {
  const std::uint32_t u = p.u, v = p.v, s = p.s;
  const bool row = side % 2 == 0;
  const std::uint32_t at = row ? (side == 0 ? v : v + s) : (side == 1 ? u + s : u);
  const std::uint32_t from = row ? u : v;
  int tileSide = -1;
  std::uint32_t m0 = from, m1 = from + s;  // steps along the tile side, from its first base vertex
  if (row && at == 0) tileSide = 0;
  if (!row && at == n) tileSide = 1;
  if (row && at == n) tileSide = 2, m0 = n - from - s, m1 = n - from;
  if (!row && at == 0) tileSide = 3, m0 = n - from - s, m1 = n - from;
  if (tileSide < 0) return {{p.chart, row ? 0u : 1u, at}, from, from + s, {}};
  const atlas::SideAcross& a = across[p.chart][std::size_t(tileSide)];
  if (a.tile != atlas::kNoTile && (a.tile < p.chart || (a.tile == p.chart && a.side < tileSide)))
    return {{a.tile, 2u + std::uint32_t(a.side), 0}, n - m1, n - m0, a};
  return {{p.chart, 2u + std::uint32_t(tileSide), 0}, m0, m1, a};
}

std::uint64_t texelKey(std::uint32_t chart, std::uint32_t u, std::uint32_t v) {
  return std::uint64_t(chart) << 16 | u << 8 | v;
}

// The texel of position `at` along `line`.
std::uint64_t texelOn(const Line& line, std::uint32_t at, std::uint32_t n) {
  if (line.kind == 0) return texelKey(line.chart, at, line.coordinate);
  if (line.kind == 1) return texelKey(line.chart, line.coordinate, at);
  const auto t = atlas::sideTexel(int(line.kind - 2), at, n + 1);
  return texelKey(line.chart, t[0], t[1]);
}

std::uint32_t log2Of(std::uint32_t powerOfTwo) { return std::uint32_t(std::countr_zero(powerOfTwo)); }

// The largest power of two dividing x > 0.
std::uint32_t lowBit(std::uint32_t x) { return x & (~x + 1); }

}  // namespace

std::vector<GpuPatch> gpuPatches(const AdaptiveMesh& mesh, const std::vector<std::array<atlas::SideAcross, 4>>& across,
                                 const std::vector<bool>& hasDetail) {
  const std::uint32_t n = mesh.chartSize() - 1;
  const auto& m = mesh.mesh();
  std::unordered_set<std::uint64_t> vertices;  // every CPU vertex, on every chart holding it
  for (const auto h : m.halfedges()) {
    if (m.is_boundary(h) || m.status(h).deleted()) continue;
    const auto x = mesh.uv(h);
    vertices.insert(texelKey(mesh.chart(h), std::uint32_t(x[0]), std::uint32_t(x[1])));
  }

  const std::vector<Patch> patches = mesh.patches();
  std::vector<GpuPatch> out(patches.size());
  struct Side {
    std::uint32_t from, to;
    std::size_t patch;
    int side;
    bool coarse;  // on a tile border whose own tile has a detail chart and the tile across none
  };
  std::unordered_map<std::uint64_t, std::pair<Line, std::vector<Side>>> lines;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Patch& p = patches[i];
    for (int k = 0; k < 4; ++k) {
      const Placed at = place(p, k, n, across);
      auto& line = lines[at.line.key()];
      line.first = at.line;
      const bool coarse = !hasDetail.empty() && hasDetail[p.chart] && at.across.tile != atlas::kNoTile && !hasDetail[at.across.tile];
      line.second.push_back({at.from, at.to, i, k, coarse});
    }
    // The inner grid must hold every CPU vertex strictly inside the patch.
    std::uint32_t spacing = p.s;
    for (std::uint32_t j = 1; j < p.s; ++j)
      for (std::uint32_t i = 1; i < p.s; ++i)
        if (vertices.count(texelKey(p.chart, p.u + i, p.v + j))) spacing = std::min({spacing, lowBit(i), lowBit(j)});
    out[i] = {p.chart, std::uint32_t(p.u) | std::uint32_t(p.v) << 16,
              std::uint32_t(p.s) | std::uint32_t(p.c) << 16 | log2Of(spacing) << 24, 0};
  }

  for (auto& [key, entry] : lines) {
    auto& [line, sides] = entry;
    std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
      return a.from != b.from ? a.from < b.from : a.to > b.to;
    });
    // Dyadic segments nest or miss each other: each class starts at a side no earlier one covers.
    for (std::size_t first = 0; first < sides.size();) {
      const std::uint32_t from = sides[first].from, to = sides[first].to;
      std::size_t last = first;
      std::uint32_t shortest = to - from;
      while (last < sides.size() && sides[last].from < to) shortest = std::min(shortest, sides[last].to - sides[last].from), ++last;
      // The largest power of two, at most the shortest side, whose multiples hold every CPU vertex
      // along the extent.
      std::uint32_t spacing = shortest;
      for (std::uint32_t at = from + 1; at < to; ++at)
        if (vertices.count(texelOn(line, at, n))) spacing = std::min(spacing, lowBit(at - from));
      const std::uint32_t bits = log2Of(spacing) | log2Of(to - from) << 3;
      for (std::size_t i = first; i < last; ++i) {
        GpuPatch& p = out[sides[i].patch];
        p.sides |= (bits | std::uint32_t(sides[i].coarse) << 6) << (8 * sides[i].side);
      }
      first = last;
    }
  }
  return out;
}

}  // namespace isoatlas::render
