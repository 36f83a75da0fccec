#include "core/polygon_triangulation.h"

#include <algorithm>
#include <limits>
#include <optional>

namespace isoatlas {
namespace {

// Past this many corners only the first corner's fan is tried: the searches below are quadratic,
// and no file seen has a polygon near it.
constexpr std::size_t kMostSearched = 256;

// Up to this many corners a polygon whose fans are all slivers or turned is split by the
// triangulation whose smallest triangle is largest (cubic in the corners), past it by ear clipping.
constexpr std::size_t kMostOptimised = 64;

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

struct Polygon {
  std::span<const Vec3> positions;
  std::span<const std::uint32_t> corners;
  Vec3 normal;       // unit Newell normal (zero for a polygon of no area)
  double tolerance;  // twice-areas at most this are "no area": relative to the polygon's size

  const Vec3& at(std::size_t i) const { return positions[corners[i]]; }
  // Twice the signed area of corners (a, b, c) along the polygon's normal: > 0 turning as it does.
  double turn(std::size_t a, std::size_t b, std::size_t c) const {
    return dot(cross(at(b) - at(a), at(c) - at(a)), normal);
  }
};

Triangles fan(const Polygon& p, std::size_t apex) {
  const std::size_t k = p.corners.size();
  Triangles out;
  for (std::size_t i = 1; i + 1 < k; ++i)
    out.push_back({p.corners[apex], p.corners[(apex + i) % k], p.corners[(apex + i + 1) % k]});
  return out;
}

// The smallest signed twice-area of the fan round `apex`.
double smallestTurn(const Polygon& p, std::size_t apex) {
  const std::size_t k = p.corners.size();
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i + 1 < k; ++i) least = std::min(least, p.turn(apex, (apex + i) % k, (apex + i + 1) % k));
  return least;
}

// Whether point q lies in triangle (a, b, c) as seen along the normal, its edges included.
bool holds(const Polygon& p, std::size_t a, std::size_t b, std::size_t c, std::size_t q) {
  const Vec3& x = p.at(q);
  if (x == p.at(a) || x == p.at(b) || x == p.at(c)) return false;  // a corner met twice (a bridge to a hole)
  auto side = [&](std::size_t u, std::size_t v) { return dot(cross(p.at(v) - p.at(u), x - p.at(u)), p.normal); };
  return side(a, b) >= 0 && side(b, c) >= 0 && side(c, a) >= 0;
}

// How well shaped triangle (a, b, c) is: twice its area over its longest side squared (0 for a
// sliver, at most sqrt(3) / 2 for an equilateral one).
double shape(const Polygon& p, std::size_t a, std::size_t b, std::size_t c) {
  const Vec3 &x = p.at(a), &y = p.at(b), &z = p.at(c);
  const double longest = std::max({dot(y - x, y - x), dot(z - y, z - y), dot(x - z, x - z)});
  return longest > 0 ? p.turn(a, b, c) / longest : 0;
}

// Ear clipping, the best shaped ear first, judged with the ears the clip leaves beside it (so a
// corner a hair off a side is not left to the end as a sliver); empty where some remaining ring has
// no ear.
Triangles ears(const Polygon& p) {
  std::vector<std::size_t> ring(p.corners.size());
  for (std::size_t i = 0; i < ring.size(); ++i) ring[i] = i;
  Triangles out;
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    std::size_t best = m;
    double bestShape = -1;
    for (std::size_t r = 0; r < m; ++r) {
      const std::size_t a = ring[(r + m - 1) % m], b = ring[r], c = ring[(r + 1) % m];
      if (!(p.turn(a, b, c) > p.tolerance)) continue;
      // The ear's shape, and that of the ears the clip makes at its two neighbours (where they turn
      // as the polygon): a good ear must not leave a sliver to be clipped later.
      double quality = shape(p, a, b, c);
      const std::size_t before = ring[(r + m - 2) % m], after = ring[(r + 2) % m];
      if (p.turn(before, a, c) > p.tolerance) quality = std::min(quality, shape(p, before, a, c));
      if (p.turn(a, c, after) > p.tolerance) quality = std::min(quality, shape(p, a, c, after));
      if (quality <= bestShape) continue;
      bool empty = true;
      for (std::size_t s = 0; s < m && empty; ++s)
        if (ring[s] != a && ring[s] != b && ring[s] != c && holds(p, a, b, c, ring[s])) empty = false;
      if (empty) best = r, bestShape = quality;
    }
    if (best == m) return {};
    out.push_back({p.corners[ring[(best + m - 1) % m]], p.corners[ring[best]], p.corners[ring[(best + 1) % m]]});
    ring.erase(ring.begin() + std::ptrdiff_t(best));
  }
  if (!(p.turn(ring[0], ring[1], ring[2]) > p.tolerance)) return {};
  out.push_back({p.corners[ring[0]], p.corners[ring[1]], p.corners[ring[2]]});
  return out;
}

// The smallest signed twice-area of `triangles` (as indices into the positions).
double smallestOf(const Polygon& p, const Triangles& triangles) {
  double least = std::numeric_limits<double>::infinity();
  for (const auto& t : triangles) {
    const Vec3 &a = p.positions[t[0]], &b = p.positions[t[1]], &c = p.positions[t[2]];
    least = std::min(least, dot(cross(b - a, c - a), p.normal));
  }
  return least;
}

// Whether segments (a, b) and (c, d) meet, seen along the normal (touching and overlapping included).
bool meet(const Polygon& p, std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
  const double abc = p.turn(a, b, c), abd = p.turn(a, b, d), cda = p.turn(c, d, a), cdb = p.turn(c, d, b);
  if (((abc > 0 && abd < 0) || (abc < 0 && abd > 0)) && ((cda > 0 && cdb < 0) || (cda < 0 && cdb > 0))) return true;
  // Collinear: whether an end of one lies on the other.
  auto on = [&](std::size_t u, std::size_t v, std::size_t w, double turn) {
    return turn == 0 && dot(p.at(w) - p.at(u), p.at(w) - p.at(v)) <= 0;
  };
  return on(a, b, c, abc) || on(a, b, d, abd) || on(c, d, a, cda) || on(c, d, b, cdb);
}

// Whether corners a and b (not neighbours) are joined by a diagonal inside the polygon: it leaves a
// into the polygon's side of a's two edges and meets no edge that does not end at a or b.
bool isDiagonal(const Polygon& p, std::size_t a, std::size_t b) {
  const std::size_t k = p.corners.size(), before = (a + k - 1) % k, after = (a + 1) % k;
  const bool inCone = p.turn(before, a, after) >= 0 ? p.turn(a, b, before) > 0 && p.turn(b, a, after) > 0
                                                    : !(p.turn(a, b, after) >= 0 && p.turn(b, a, before) >= 0);
  if (!inCone) return false;
  for (std::size_t e = 0; e < k; ++e) {
    const std::size_t f = (e + 1) % k;
    if (e == a || e == b || f == a || f == b) continue;
    if (meet(p, a, b, e, f)) return false;
  }
  return true;
}

// The triangulation whose smallest triangle is largest (dynamic programming over the diagonals,
// O(k^3)); empty where none has every triangle turning as the polygon (it crosses itself).
Triangles largestSmallest(const Polygon& p) {
  const std::size_t k = p.corners.size();
  std::vector<std::uint8_t> joined(k * k, 0);  // the polygon's sides and its diagonals
  for (std::size_t a = 0; a < k; ++a) {
    joined[a * k + (a + 1) % k] = joined[((a + 1) % k) * k + a] = 1;
    for (std::size_t b = a + 2; b < k; ++b)
      if (!(a == 0 && b + 1 == k) && isDiagonal(p, a, b) && isDiagonal(p, b, a)) joined[a * k + b] = joined[b * k + a] = 1;
  }
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  std::vector<double> best(k * k, kNone);  // best[i k + j]: the chain i .. j closed by j -> i
  std::vector<std::size_t> apex(k * k, 0);
  for (std::size_t i = 0; i + 1 < k; ++i) best[i * k + i + 1] = std::numeric_limits<double>::infinity();
  for (std::size_t gap = 2; gap < k; ++gap)
    for (std::size_t i = 0; i + gap < k; ++i) {
      const std::size_t j = i + gap;
      if (!joined[i * k + j]) continue;
      for (std::size_t m = i + 1; m < j; ++m) {
        const double turn = p.turn(i, m, j);
        if (!(turn > p.tolerance) || !joined[i * k + m] || !joined[m * k + j]) continue;
        const double least = std::min({turn, best[i * k + m], best[m * k + j]});
        if (least > best[i * k + j]) best[i * k + j] = least, apex[i * k + j] = m;
      }
    }
  if (best[k - 1] == kNone) return {};
  Triangles out;
  std::vector<std::pair<std::size_t, std::size_t>> chains{{0, k - 1}};
  while (!chains.empty()) {
    const auto [i, j] = chains.back();
    chains.pop_back();
    if (j - i < 2) continue;
    const std::size_t m = apex[i * k + j];
    out.push_back({p.corners[i], p.corners[m], p.corners[j]});
    chains.push_back({i, m}), chains.push_back({m, j});
  }
  return out;
}

// A polygon that meets itself at a vertex (two loops joined there, or a spike out and back) split
// there into its loops, each triangulated alone; nullopt for a polygon that meets itself nowhere.
std::optional<Triangles> splitWhereItMeetsItself(std::span<const Vec3> positions, std::span<const std::uint32_t> corners) {
  const std::size_t k = corners.size();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j) {
      if (corners[i] != corners[j]) continue;
      std::vector<std::uint32_t> inner(corners.begin() + std::ptrdiff_t(i), corners.begin() + std::ptrdiff_t(j));
      std::vector<std::uint32_t> outer(corners.begin(), corners.begin() + std::ptrdiff_t(i));
      outer.insert(outer.end(), corners.begin() + std::ptrdiff_t(j), corners.end());
      Triangles out;
      for (const auto& loop : {inner, outer})
        for (const auto& t : triangulatePolygon(positions, loop)) out.push_back(t);
      return out;
    }
  return std::nullopt;
}

}  // namespace

Vec3 newellNormal(std::span<const Vec3> positions, std::span<const std::uint32_t> corners) {
  Vec3 n{0, 0, 0};
  const std::size_t k = corners.size();
  if (k < 3) return n;
  const Vec3& o = positions[corners[0]];  // about a corner, not the origin: far from it, the sum would cancel
  for (std::size_t i = 1; i + 1 < k; ++i) n = n + cross(positions[corners[i]] - o, positions[corners[i + 1]] - o);
  return n;
}

Triangles triangulatePolygon(std::span<const Vec3> positions, std::span<const std::uint32_t> corners) {
  const std::size_t k = corners.size();
  Polygon p{positions, corners, {0, 0, 0}, 0};
  if (k < 3) return {};
  if (k == 3) return fan(p, 0);
  if (k <= kMostSearched)
    if (std::optional<Triangles> loops = splitWhereItMeetsItself(positions, corners)) return *loops;
  const Vec3 n = newellNormal(positions, corners);
  if (norm(n) > 0) p.normal = unit(n);
  double extent = 0;  // the polygon's size squared: "no area" is relative to it
  for (std::size_t i = 1; i < k; ++i) extent = std::max(extent, dot(p.at(i) - p.at(0), p.at(i) - p.at(0)));
  p.tolerance = 1e-12 * extent;

  const std::size_t searched = k <= kMostSearched ? k : 1;
  const double sliver = 1e-6 * norm(n);  // a triangle this thin samples the model's charts onto a line
  for (std::size_t apex = 0; apex < searched; ++apex)
    if (const double least = smallestTurn(p, apex); least > p.tolerance) {
      if (least < sliver) {
        Triangles t = k <= kMostOptimised ? largestSmallest(p) : ears(p);
        if (!t.empty() && smallestOf(p, t) > least) return t;
      }
      return fan(p, apex);
    }
  if (k <= kMostOptimised)
    if (Triangles t = largestSmallest(p); !t.empty()) return t;
  if (k <= kMostSearched)
    if (Triangles t = ears(p); !t.empty()) return t;
  // Crossing itself, or of no area: the fan whose smallest triangle is largest, by unsigned area.
  std::size_t best = 0;
  double bestArea = -1;
  for (std::size_t apex = 0; apex < searched; ++apex) {
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i + 1 < k; ++i)
      least = std::min(least, norm(cross(p.at((apex + i) % k) - p.at(apex), p.at((apex + i + 1) % k) - p.at(apex))));
    if (least > bestArea) bestArea = least, best = apex;
  }
  return fan(p, best);
}

}  // namespace isoatlas
