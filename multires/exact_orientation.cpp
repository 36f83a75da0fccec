#include "multires/exact_orientation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace isoatlas::multires {

int exactOrientationSlow(const Vec2& a, const Vec2& b, const Vec2& c) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_2;
  return int(CGAL::orientation(Point(a.x, a.y), Point(b.x, b.y), Point(c.x, c.y)));
}

}  // namespace isoatlas::multires
