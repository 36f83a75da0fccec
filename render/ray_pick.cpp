#include "render/ray_pick.h"

#include <cmath>
#include <limits>

namespace isoatlas::render {

std::optional<Vec3> rayPick(const Mesh& mesh, const Vec3& origin, const Vec3& direction) {
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    if (c.size() != 3) continue;
    const Vec3 a = mesh.positions[c[0]], e1 = mesh.positions[c[1]] - a, e2 = mesh.positions[c[2]] - a;
    const Vec3 p = cross(direction, e2);
    const double det = dot(e1, p);
    if (std::fabs(det) < 1e-14) continue;  // parallel to the triangle
    const Vec3 s = origin - a, q = cross(s, e1);
    const double u = dot(s, p) / det, v = dot(direction, q) / det, t = dot(e2, q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && t > 0) nearest = std::min(nearest, t);
  }
  if (!std::isfinite(nearest)) return std::nullopt;
  return origin + direction * nearest;
}

}  // namespace isoatlas::render
