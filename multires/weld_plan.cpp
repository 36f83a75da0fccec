#include "multires/weld_plan.h"

#include <cmath>

#include "multires/exact_orientation.h"

namespace isoatlas::multires {

bool starIsValid(std::span<const Vec2> plane, bool boundary) {
  const std::size_t k = plane.size();
  const std::size_t faces = boundary ? k - 1 : k;
  for (std::size_t i = 0; i < faces; ++i)
    if (exactOrientation({0, 0}, plane[i], plane[(i + 1) % k]) <= 0) return false;
  return true;
}

namespace {

// The counter-clockwise angle at the origin from a to b as a pseudo-angle in [0, 4): it grows with
// the angle (0 .. 2 pi), which is all a comparison needs, without atan2.
double angleBetween(const Vec2& a, const Vec2& b) {
  const double x = a.x * b.x + a.y * b.y, y = cross2(a, b);
  const double sum = std::abs(x) + std::abs(y);
  if (!(sum > 0)) return 0;
  if (y >= 0) return x >= 0 ? y / sum : 1 - x / sum;
  return x < 0 ? 2 - y / sum : 3 + x / sum;
}

}  // namespace

bool planWeld(std::span<const Vec2> plane, bool boundary, std::size_t t, WeldPlan& plan) {
  const std::size_t k = plane.size();
  const Vec2 origin{0, 0};
  const Vec2& u = plane[t];
  auto at = [&](std::size_t i) -> const Vec2& { return plane[(i + k) % k]; };
  plan.target = t;
  plan.flipCount = 0;
  // Flipping spoke l on u's clockwise side: diamond (v, w_l-1, w_l, u) -> edge (u, w_l-1). On its
  // counter-clockwise side, spoke r: diamond (v, u, w_r, w_r+1) -> edge (u, w_r+1).
  auto convexBefore = [&](std::size_t l) {
    return exactOrientation(at(l - 1), at(l), u) > 0 && exactOrientation(origin, at(l - 1), u) > 0;
  };
  auto convexAfter = [&](std::size_t r) {
    return exactOrientation(u, at(r), at(r + 1)) > 0 && exactOrientation(origin, u, at(r + 1)) > 0;
  };
  std::size_t l = t + k - 1, r = t + 1;  // the spokes next to u (indices taken mod k)
  if (boundary) {
    // One side only: from u at one end of the open ring towards the other, down to two faces.
    for (std::size_t j = 1; j + 2 < k; ++j) {
      const std::size_t spoke = t == 0 ? j : k - 1 - j;
      if (!(t == 0 ? convexAfter(spoke) : convexBefore(spoke))) return false;
      plan.flips[plan.flipCount++] = spoke;
    }
  } else {
    for (std::size_t degree = k; degree > 4; --degree) {
      // The narrower of the two triangles the flips would leave at v goes first.
      const bool left = angleBetween(at(l - 1), u) <= angleBetween(u, at(r + 1));
      if (left ? convexBefore(l) : convexAfter(r)) {
        plan.flips[plan.flipCount++] = left ? l-- % k : r++ % k;
      } else if (left ? convexAfter(r) : convexBefore(l)) {
        plan.flips[plan.flipCount++] = left ? r++ % k : l-- % k;
      } else {
        return false;
      }
    }
  }
  // The fan: the ring from t's successor round to its predecessor (on a boundary, the open ring
  // without t).
  plan.rimSize = 0;
  for (std::size_t j = 1; j < k; ++j) plan.rim[plan.rimSize++] = boundary ? (t == 0 ? j : j - 1) : (t + j) % k;
  for (std::size_t m = 0; m + 1 < plan.rimSize; ++m)
    if (exactOrientation(u, plane[plan.rim[m]], plane[plan.rim[m + 1]]) <= 0) return false;
  return true;
}

}  // namespace isoatlas::multires
