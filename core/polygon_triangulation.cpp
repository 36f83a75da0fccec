#include "core/polygon_triangulation.h"

#include <algorithm>
#include <limits>

namespace isoatlas {
namespace {

// Past this many corners only the first corner's fan is tried: the searches below are quadratic,
// and no file seen has a polygon near it.
constexpr std::size_t kMostSearched = 256;

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

// Ear clipping; empty where some remaining ring has no ear.
Triangles ears(const Polygon& p) {
  std::vector<std::size_t> ring(p.corners.size());
  for (std::size_t i = 0; i < ring.size(); ++i) ring[i] = i;
  Triangles out;
  std::size_t start = 0;
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    for (std::size_t step = 0; step < m && !clipped; ++step) {
      const std::size_t r = (start + step) % m;
      const std::size_t a = ring[(r + m - 1) % m], b = ring[r], c = ring[(r + 1) % m];
      if (!(p.turn(a, b, c) > p.tolerance)) continue;
      bool empty = true;
      for (std::size_t s = 0; s < m && empty; ++s)
        if (ring[s] != a && ring[s] != b && ring[s] != c && holds(p, a, b, c, ring[s])) empty = false;
      if (!empty) continue;
      out.push_back({p.corners[a], p.corners[b], p.corners[c]});
      ring.erase(ring.begin() + std::ptrdiff_t(r));
      start = r % ring.size();
      clipped = true;
    }
    if (!clipped) return {};
  }
  if (!(p.turn(ring[0], ring[1], ring[2]) > p.tolerance)) return {};
  out.push_back({p.corners[ring[0]], p.corners[ring[1]], p.corners[ring[2]]});
  return out;
}

}  // namespace

Vec3 newellNormal(std::span<const Vec3> positions, std::span<const std::uint32_t> corners) {
  Vec3 n{0, 0, 0};
  const std::size_t k = corners.size();
  const Vec3& o = positions[corners[0]];  // about a corner, not the origin: far from it, the sum would cancel
  for (std::size_t i = 1; i + 1 < k; ++i) n = n + cross(positions[corners[i]] - o, positions[corners[i + 1]] - o);
  return n;
}

Triangles triangulatePolygon(std::span<const Vec3> positions, std::span<const std::uint32_t> corners) {
  const std::size_t k = corners.size();
  Polygon p{positions, corners, {0, 0, 0}, 0};
  if (k == 3) return fan(p, 0);
  const Vec3 n = newellNormal(positions, corners);
  if (norm(n) > 0) p.normal = unit(n);
  double extent = 0;  // the polygon's size squared: "no area" is relative to it
  for (std::size_t i = 1; i < k; ++i) extent = std::max(extent, dot(p.at(i) - p.at(0), p.at(i) - p.at(0)));
  p.tolerance = 1e-12 * extent;

  const std::size_t searched = k <= kMostSearched ? k : 1;
  for (std::size_t apex = 0; apex < searched; ++apex)
    if (smallestTurn(p, apex) > p.tolerance) return fan(p, apex);
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
