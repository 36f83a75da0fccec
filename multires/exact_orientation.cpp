#include "multires/exact_orientation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

namespace isoatlas::multires {

int exactOrientationSlow(const Vec2& a, const Vec2& b, const Vec2& c) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_2;
  return int(CGAL::orientation(Point(a.x, a.y), Point(b.x, b.y), Point(c.x, c.y)));
}

std::array<double, 3> exactBarycentricSlow(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  using Q = CGAL::Exact_rational;
  auto orient = [](const Vec2& u, const Vec2& v, const Vec2& w) -> Q {  // Q, not an expression of temporaries
    return (Q(u.x) - Q(w.x)) * (Q(v.y) - Q(w.y)) - (Q(u.y) - Q(w.y)) * (Q(v.x) - Q(w.x));
  };
  const Q area = orient(a, b, c);
  if (area == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};  // collinear: no weights hold p, as barycentric2 says
  const Q wa = orient(p, b, c) / area, wb = orient(a, p, c) / area, wc = Q(1) - wa - wb;
  return {CGAL::to_double(wa), CGAL::to_double(wb), CGAL::to_double(wc)};
}

}  // namespace isoatlas::multires
