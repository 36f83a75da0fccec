// Vec2: a point of a flat chart (an exponential map, a base-domain chart), with the orientation and
// barycentric coordinates every flat test uses.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>

namespace isoatlas::multires {

struct Vec2 {
  double x = 0, y = 0;
  Vec2 operator+(const Vec2& o) const { return {x + o.x, y + o.y}; }
  Vec2 operator-(const Vec2& o) const { return {x - o.x, y - o.y}; }
  Vec2 operator*(double s) const { return {x * s, y * s}; }
};
inline double cross2(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }
// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline double orient2(const Vec2& a, const Vec2& b, const Vec2& c) { return cross2(b - a, c - a); }

// Barycentric coordinates of p in triangle (a, b, c); any sign; thirds for a flat triangle.
inline std::array<double, 3> barycentric2(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const double area = orient2(a, b, c);
  if (area == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double wa = orient2(p, b, c) / area, wb = orient2(a, p, c) / area;
  return {wa, wb, 1 - wa - wb};
}

// Barycentric weights (summing to one) moved onto their triangle: negatives to zero, renormalised.
inline void clampToTriangle(std::array<double, 3>& w) {
  double sum = 0;
  for (double& x : w) sum += (x = x > 0 ? x : 0);
  if (sum == 1) return;  // dividing by it would change nothing
  for (double& x : w) x /= sum;  // they summed to one, so one at least stays positive
}

// A list of `count` taken round from `hint` on: the first index, and the one after t (no division:
// the searches call it on every try).
inline std::size_t firstRound(std::size_t hint, std::size_t count) { return hint < count ? hint : count ? hint % count : 0; }
inline std::size_t nextRound(std::size_t t, std::size_t count) { return t + 1 == count ? 0 : t + 1; }

// Which of `count` flat triangles holds p best (largest smallest weight; outside all only by
// rounding), tried from `hint` on and stopping at the first that holds it; the weights are clamped
// onto that triangle. corners(i) gives triangle i's three corners; flat ones are passed over, and
// kNoTriangleHit says that none was left.
inline constexpr std::size_t kNoTriangleHit = ~std::size_t(0);
struct TriangleHit {
  std::size_t triangle = kNoTriangleHit;
  std::array<double, 3> bary{};
  bool holds = false;  // the triangle holds p (before clamping); else it is only the nearest
};
template <class Corners>
TriangleHit locateInTriangles(const Vec2& p, std::size_t count, const Corners& corners, std::size_t hint = 0) {
  // The best so far in locals rather than a TriangleHit: rewriting the struct piecewise stalled the
  // next read of it.
  std::size_t best = kNoTriangleHit;
  std::array<double, 3> bestBary{};
  double bestLowest = -std::numeric_limits<double>::infinity();
  std::size_t t = firstRound(hint, count);
  for (std::size_t m = 0; m < count; ++m, t = nextRound(t, count)) {
    const std::array<Vec2, 3> c = corners(t);
    if (orient2(c[0], c[1], c[2]) == 0) continue;
    const auto b = barycentric2(p, c[0], c[1], c[2]);
    const double lowest = std::min({b[0], b[1], b[2]});
    if (lowest > bestLowest) bestLowest = lowest, best = t, bestBary = b;
    if (lowest >= 0) break;
  }
  if (best == kNoTriangleHit) return {};
  TriangleHit hit{best, bestBary, bestLowest >= 0};
  clampToTriangle(hit.bary);
  return hit;
}

}  // namespace isoatlas::multires
