#include "atlas/separate_codes.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

#include "atlas/code_shell.h"

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

SeparatedTexels separateJoinedTexels(const Atlas& atlas, std::vector<QuantisedChart>& charts, Atlas& decoded) {
  const AtlasLayout& layout = atlas.layout;
  const std::uint32_t n = layout.chartSize;

  std::unordered_map<Position, std::size_t, PositionBits> taken;  // decoded position -> its texel in the image
  taken.reserve(std::size_t(layout.charts) * n * n);
  auto inside = [&](std::uint32_t i, std::uint32_t j) { return i > 0 && j > 0 && i + 1 < n && j + 1 < n; };
  // Texel (c, i, j) off the border to the nearest code round its own whose position no texel takes.
  auto moveApart = [&](std::uint32_t c, std::uint32_t i, std::uint32_t j) {
    QuantisedChart& q = charts[c];
    std::array<std::uint16_t, 3>& code = q.positions[std::size_t(j) * n + i];
    const Position& want = atlas.positions[layout.texel(c, i, j)];
    for (int reach = 1; reach <= 3; ++reach) {
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
    return decoded.positions[layout.texel(c, i, j)];  // no free code near: left joined
  };

  SeparatedTexels out;
  for (std::uint32_t c = 0; c < layout.charts; ++c)
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t at = layout.texel(c, i, j);
        const auto [it, fresh] = taken.emplace(decoded.positions[at], at);
        if (fresh || atlas.positions[it->second] == atlas.positions[at]) continue;
        // Joined by the codes alone: the texel off a border moves (this one first).
        const std::size_t other = it->second;
        const std::uint32_t x = std::uint32_t(other % layout.width()), y = std::uint32_t(other / layout.width());
        const std::uint32_t oc = (y / n) * layout.columns + x / n, oi = x % n, oj = y % n;
        std::size_t moving = at;
        std::uint32_t mc = c, mi = i, mj = j;
        if (!inside(i, j)) {
          if (!inside(oi, oj)) {
            ++out.joined;
            continue;
          }
          moving = other, mc = oc, mi = oi, mj = oj;
          it->second = at;  // the place stays with this texel
        }
        const Position p = moveApart(mc, mi, mj);
        if (p == decoded.positions[moving]) {
          ++out.joined;
          continue;
        }
        decoded.positions[moving] = p;
        taken.emplace(p, moving);
        ++out.moved;
      }
  return out;
}

}  // namespace isoatlas::atlas
