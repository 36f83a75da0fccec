#include "atlas/separate_codes.h"

#include <algorithm>
#include <bit>
#include <optional>
#include <unordered_map>

#include "atlas/code_shell.h"
#include "atlas/tile_sides.h"

namespace isoatlas::atlas {
namespace {

using Position = std::array<float, 3>;

struct PositionBits {
  std::size_t operator()(const Position& p) const {
    const std::uint64_t h = std::bit_cast<std::uint32_t>(p[0]) * 0x9E3779B97F4A7C15ull ^
                            std::bit_cast<std::uint32_t>(p[1]) * 0xC2B2AE3D27D4EB4Full ^
                            std::bit_cast<std::uint32_t>(p[2]) * 0x165667B19E3779F9ull;
    return std::size_t(h ^ (h >> 29));
  }
};

double distance2(const Position& a, const Position& b) {
  const double x = double(a[0]) - b[0], y = double(a[1]) - b[1], z = double(a[2]) - b[2];
  return x * x + y * y + z * z;
}

}  // namespace

SeparatedTexels separateJoinedTexels(const Atlas& atlas, const multires::BaseMesh& base, std::vector<QuantisedChart>& charts,
                                     Atlas& decoded) {
  const AtlasLayout& layout = atlas.layout;
  const std::uint32_t n = layout.chartSize;
  const auto across = sidesAcross(base);

  std::unordered_map<Position, std::size_t, PositionBits> taken;  // decoded position -> its texel in the image
  taken.reserve(std::size_t(layout.charts) * n * n);
  auto inside = [&](std::uint32_t i, std::uint32_t j) { return i > 0 && j > 0 && i + 1 < n && j + 1 < n; };
  // Texel (c, i, j)'s code to the nearest round its own whose position no texel takes; returns the
  // position it then decodes to (its own, where no free code lies near).
  auto moveApart = [&](std::uint32_t c, std::uint32_t i, std::uint32_t j) {
    QuantisedChart& q = charts[c];
    std::array<std::uint16_t, 3>& code = q.positions[std::size_t(j) * n + i];
    const Position& want = atlas.positions[layout.texel(c, i, j)];
    for (int reach = 1; reach <= 4; ++reach) {
      double best = -1;
      std::array<std::uint16_t, 3> bestCode{};
      forEachCodeInShell(q, code, reach, [&](const std::array<std::uint16_t, 3>& next) {
        const Position p = decodePosition(q, next);
        if (taken.contains(p)) return;
        const double e = distance2(p, want);
        if (best < 0 || e < best) best = e, bestCode = next;
      });
      if (best >= 0) {
        code = bestCode;
        return decodePosition(q, code);
      }
    }
    return decoded.positions[layout.texel(c, i, j)];
  };
  // The texels that decode from one code: an inner texel alone; a side texel (not a corner) with its
  // copy across, from the lower-numbered chart's code (as dequantiseAtlas copies it). A corner: none
  // (it decodes from its base vertex's first chart, or is the base vertex itself).
  struct OneCode {
    std::uint32_t c = 0, i = 0, j = 0;  // the texel whose code it is
    std::size_t texels[2] = {~std::size_t(0), ~std::size_t(0)};
  };
  auto oneCode = [&](std::uint32_t c, std::uint32_t i, std::uint32_t j) -> std::optional<OneCode> {
    if (inside(i, j)) return OneCode{c, i, j, {layout.texel(c, i, j), ~std::size_t(0)}};
    const bool corner = (i == 0 || i + 1 == n) && (j == 0 || j + 1 == n);
    if (corner) return std::nullopt;
    const int s = j == 0 ? 0 : i + 1 == n ? 1 : j + 1 == n ? 2 : 3;
    const std::uint32_t m = s == 0 ? i : s == 1 ? j : s == 2 ? n - 1 - i : n - 1 - j;
    const SideAcross other = across[c][s];
    if (other.tile == kNoTile) return OneCode{c, i, j, {layout.texel(c, i, j), ~std::size_t(0)}};
    const auto kl = sideTexel(other.side, n - 1 - m, n);
    const std::size_t here = layout.texel(c, i, j), there = layout.texel(other.tile, kl[0], kl[1]);
    if (c < other.tile) return OneCode{c, i, j, {here, there}};
    return OneCode{other.tile, kl[0], kl[1], {there, here}};
  };
  auto chartOf = [&](std::size_t texel) {
    const std::uint32_t x = std::uint32_t(texel % layout.width()), y = std::uint32_t(texel / layout.width());
    return std::array<std::uint32_t, 3>{(y / n) * layout.columns + x / n, x % n, y % n};
  };

  SeparatedTexels out;
  for (std::uint32_t c = 0; c < layout.charts; ++c)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t at = layout.texel(c, i, j);
        const auto [it, fresh] = taken.emplace(decoded.positions[at], at);
        if (fresh || atlas.positions[it->second] == atlas.positions[at]) continue;
        // Joined by the codes alone. An inner texel moves first (this one, else the other): its code
        // is its own. Else a side's code moves, in the chart its copies decode from (this one first:
        // the other's copies may already be placed); corners stay.
        const std::size_t other = it->second;
        const auto [oc, oi, oj] = chartOf(other);
        std::optional<OneCode> move;
        bool movingOther = false;
        if (inside(i, j)) move = oneCode(c, i, j);
        else if (inside(oi, oj)) move = oneCode(oc, oi, oj), movingOther = true;
        else if ((move = oneCode(c, i, j)) && move->texels[0] == at) {
        } else if ((move = oneCode(oc, oi, oj))) movingOther = true;
        if (!move) {
          ++out.joined;
          continue;
        }
        const Position p = moveApart(move->c, move->i, move->j);
        if (p == decoded.positions[move->texels[0]]) {
          ++out.joined;
          continue;
        }
        if (movingOther) it->second = at;  // the place stays with this texel
        for (const std::size_t t : move->texels)
          if (t != ~std::size_t(0)) decoded.positions[t] = p;
        taken.emplace(p, move->texels[0]);
        ++(inside(move->i, move->j) ? out.moved : out.movedOnSides);
      }
  return out;
}

}  // namespace isoatlas::atlas
