// Exact orientation of flat triangles (CGAL's Epick orientation_2: a floating-point filter with an
// exact fallback), for the decisions the parametrisation's bijectivity rests on: a triangle of a
// layout is valid, a point lies in a triangle. The coordinates are taken as given; the answer is
// exact for them.
#pragma once
#include <array>
#include <cmath>

#include "multires/vec2.h"

namespace isoatlas::multires {

// The exact test alone (CGAL), for the cases the filter below cannot decide.
int exactOrientationSlow(const Vec2& a, const Vec2& b, const Vec2& c);

// p's barycentric weights in the counter-clockwise triangle (a, b, c), computed exactly (rationals)
// and each rounded to double: for triangles too thin for the floating-point ones.
std::array<double, 3> exactBarycentricSlow(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c);

// The floating-point orientation determinant of (a, b, c) and its rounding bound (Shewchuk's orient2d
// filter): its sign is certain when |det| exceeds the bound.
struct FilteredOrientation {
  double det, bound;
};
inline FilteredOrientation filteredOrientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double left = (a.x - c.x) * (b.y - c.y), right = (a.y - c.y) * (b.x - c.x);
  constexpr double kBound = 3.3306690738754716e-16;  // (3 + 16 eps) eps
  return {left - right, kBound * (std::abs(left) + std::abs(right))};
}

// +1 when (a, b, c) turns counter-clockwise, -1 clockwise, 0 when the three are collinear. The
// floating-point determinant decides when it exceeds its rounding bound, which is nearly always; the
// rest goes to CGAL.
inline int exactOrientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  const auto [det, bound] = filteredOrientation(a, b, c);
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exactOrientationSlow(a, b, c);
}

// Whether the counter-clockwise triangle (a, b, c) holds p (its boundary included).
inline bool exactlyInTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  return exactOrientation(a, b, p) >= 0 && exactOrientation(b, c, p) >= 0 && exactOrientation(c, a, p) >= 0;
}

// p's barycentric weights in the counter-clockwise triangle (a, b, c): in floating point, unless the
// triangle is so thin that its floating-point area keeps fewer than about 30 correct bits (or rounds
// to zero, where barycentric2 would give the centroid); then exactly.
inline std::array<double, 3> barycentricInTriangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const auto [det, bound] = filteredOrientation(a, b, c);
  if (std::abs(det) > 1e6 * bound) return barycentric2(p, a, b, c);  // ~20 bits spent of 53
  return exactBarycentricSlow(p, a, b, c);
}

// p's orientation against each side of triangle c (side i faces corner i), and the hit it makes when
// none is negative.
inline std::array<int, 3> sideOrientations(const Vec2& p, const std::array<Vec2, 3>& c) {
  return {exactOrientation(c[1], c[2], p), exactOrientation(c[2], c[0], p), exactOrientation(c[0], c[1], p)};
}
inline TriangleHit hitIn(const Vec2& p, std::size_t t, const std::array<Vec2, 3>& c, const std::array<int, 3>& o) {
  TriangleHit hit{t, barycentricInTriangle(p, c[0], c[1], c[2]), true};
  for (int i = 0; i < 3; ++i)
    if (o[std::size_t(i)] == 0) hit.bary[std::size_t(i)] = 0;
  clampToTriangle(hit.bary);
  return hit;
}

// Which of `count` counter-clockwise triangles holds p by exact tests, tried from `hint` on, and p's
// weights there: a corner whose opposite edge holds p exactly gets weight 0 exactly (so the point
// is on that edge for the next step, which carries it along edges it keeps), the others are
// computed in floating point and rounded onto the triangle. kNoTriangleHit when none holds p. corners(i) gives triangle i's corners.
template <class Corners>
TriangleHit locateExactly(const Vec2& p, std::size_t count, const Corners& corners, std::size_t hint = 0) {
  std::size_t t = firstRound(hint, count);
  for (std::size_t m = 0; m < count; ++m, t = nextRound(t, count)) {
    const std::array<Vec2, 3> c = corners(t);
    const std::array<int, 3> o = sideOrientations(p, c);
    if (o[0] >= 0 && o[1] >= 0 && o[2] >= 0) return hitIn(p, t, c, o);
  }
  return {};
}

// The triangle that holds p strictly inside, where no other triangle of a triangulation can hold it
// (so the hit locateExactly gives, whatever order it tries them in), walked to from triangle `from`
// across a side p lies beyond. across(t, i): the triangle across triangle t's side i (the side
// facing corner i), or kNoTriangleHit. None when the walk meets p on a side, leaves the triangles or
// makes `count` moves: the full test decides those.
template <class Corners, class Across>
TriangleHit walkStrictlyInside(const Vec2& p, std::size_t from, std::size_t count, const Corners& corners, const Across& across) {
  std::size_t t = from;
  for (std::size_t moves = 0; moves < count && t != kNoTriangleHit; ++moves) {
    const std::array<Vec2, 3> c = corners(t);
    const std::array<int, 3> o = sideOrientations(p, c);
    if (o[0] > 0 && o[1] > 0 && o[2] > 0) return hitIn(p, t, c, o);
    const int side = o[0] < 0 ? 0 : o[1] < 0 ? 1 : o[2] < 0 ? 2 : -1;
    if (side < 0) break;
    t = across(t, side);
  }
  return {};
}

}  // namespace isoatlas::multires
