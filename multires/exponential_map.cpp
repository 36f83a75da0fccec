#include "multires/exponential_map.h"

#include <numbers>

namespace isoatlas::multires {

bool exponentialMap(const StellarMesh& mesh, VertexH v, const OneRing& ring, std::vector<Vec2>& plane) {
  const std::size_t k = ring.vertices.size();
  if (k > kMaxDegree) return false;
  const Vec3 centre = toVec3(mesh.point(v));
  Vec3 directions[kMaxDegree];
  double radius[kMaxDegree], angle[kMaxDegree];
  for (std::size_t i = 0; i < k; ++i) {
    const Vec3 d = toVec3(mesh.point(ring.vertices[i])) - centre;
    radius[i] = norm(d);
    if (!(radius[i] > 0)) return false;
    directions[i] = d * (1 / radius[i]);
  }
  // Angle of each face at v; the faces are (v, w_i, w_i+1).
  double total = 0;
  for (std::size_t i = 0; i < ring.faces.size(); ++i) {
    const Vec3& a = directions[i];
    const Vec3& b = directions[(i + 1) % k];
    angle[i] = std::atan2(norm(cross(a, b)), dot(a, b));
    total += angle[i];
  }
  if (!(total > 1e-12)) return false;
  const double scale = (ring.boundary ? std::numbers::pi : 2 * std::numbers::pi) / total;
  plane.resize(k);
  double phi = 0;
  for (std::size_t i = 0; i < k; ++i) {
    plane[i] = {radius[i] * std::cos(phi), radius[i] * std::sin(phi)};
    if (i < ring.faces.size()) phi += scale * angle[i];
  }
  // A boundary vertex lies exactly on the line between its boundary neighbours (sin of the rounded
  // half turn is not 0), so that a boundary weld's fan still holds it by exact test.
  if (ring.boundary) plane[k - 1] = {-radius[k - 1], 0};
  return true;
}

}  // namespace isoatlas::multires
