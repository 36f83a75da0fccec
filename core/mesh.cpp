#include "core/mesh.h"

#include <algorithm>

namespace isoatlas {

bool Mesh::allFacesHave(std::size_t corners) const {
  for (std::size_t f = 0; f < faceCount(); ++f)
    if (faceOffsets[f + 1] - faceOffsets[f] != corners) return false;
  return true;
}

Box boundingBox(const std::vector<Vec3>& points) {
  if (points.empty()) return {};
  Box b{points[0], points[0]};
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) {
      b.min[a] = std::min(b.min[a], p[a]);
      b.max[a] = std::max(b.max[a], p[a]);
    }
  return b;
}

}  // namespace isoatlas
